#pragma once
// Progress of long host work that reports in lines rather than fractions (fit iterations,
// scenario stages, wear-id starts), in the one style of amb-host: stderr only (stdout may
// carry JSON), "LABEL: text", a line at most every `period_s` (the first one at once), so a
// terminal shows that work goes on and a log stays short.
// --quiet: do not install it.
#include <functional>
#include <string>

namespace amb::host::ui {

/// A callback printing progress lines as described above. `label`: e.g. "fit".
std::function<void(const std::string&)> periodic_lines(const std::string& label, double period_s = 2.0);

}  // namespace amb::host::ui
