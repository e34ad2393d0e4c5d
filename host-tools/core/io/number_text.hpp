#pragma once
// The host's one number formatter: printf formats into a std::string of any length (no
// fixed buffer to truncate into). Host code that writes numbers into text (reports, messages,
// CSV, progress lines) uses this instead of a file-local snprintf helper. The format is
// checked against the arguments at compile time when it is a literal.
#include <string>

namespace amb::host::io {

/// `printf_format` applied to the values that follow, e.g.
/// printf_text("%.3f s", 1.5) == "1.500 s". Numbers and C strings only (printf's rules).
std::string printf_text(const char* printf_format, ...) __attribute__((format(printf, 1, 2)));

/// `v` with 17 significant digits ("%.17g"): reads back as the same double.
std::string exact_text(double v);

}  // namespace amb::host::io
