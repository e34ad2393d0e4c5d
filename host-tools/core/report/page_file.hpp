#pragma once
// Writing a rendered HTML page to its file: the event report and the sweep page.
#include <string>

namespace amb::host::report {

/// The start of a self-contained HTML page up to and including <body>: the title, the CSS the
/// pages share (body, headings, .sub, .row, svg.plot, table.facts, .caption, footer) and
/// `extra_css` (page-specific rules).
std::string page_head(const std::string& title, const std::string& extra_css);

/// Writes `html` to `path` (made absolute; missing parent folders are created) and returns the
/// absolute path. Throws std::runtime_error naming `what` (e.g. "report") and the path:
/// "cannot write the <what> to '<path>'<open_hint>" when the file cannot be opened,
/// "writing the <what> to '<path>' failed (disk full?)" when the write fails.
std::string write_page_file(const std::string& html, const std::string& path, const std::string& what,
                            const std::string& open_hint = "");

}  // namespace amb::host::report
