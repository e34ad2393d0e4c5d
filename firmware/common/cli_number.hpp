#pragma once
// The number check of every command line (amb-host, amb-firmware, amb-plant): a value is a
// finite number written in full ("abc", "1e3x", "inf", "nan" refused) inside the option's
// range. Header-only and free of dependencies so the firmware executables (also built for the
// ARM target) and the host tools share one rule and one wording. Not for the loop step (it
// builds strings).
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace amb::cli {

/// The allowed values of a numeric option. `lo`/`hi`: bounds in the option's unit;
/// `lo_open`: `lo` itself is refused (a value must be > lo); `integer`: whole numbers only.
struct NumberRange {
  double lo = 0.0;
  double hi = 0.0;
  bool lo_open = false;
  bool integer = false;
  const char* unit = "";  ///< printed after the range, e.g. "Hz", "s"; "" for a pure number
};

/// The range as the help and the errors write it: "[1, 65535]" or "(0, 1e+06] Hz".
inline std::string describe(const NumberRange& r) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s%.6g, %.6g]%s%s%s", r.lo_open ? "(" : "[", r.lo, r.hi, *r.unit ? " " : "", r.unit,
                r.integer ? " (whole number)" : "");
  return buf;
}

/// Checks `text` against `r`. Returns "" when it is a finite number in range (and stores it in
/// `*value` if given), else why not, without the option's name (the caller prefixes it).
inline std::string check_number(const std::string& text, const NumberRange& r, double* value = nullptr) {
  const std::string allowed = "; allowed " + describe(r);
  if (text.empty()) return "no value given" + allowed;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0') return "'" + text + "' is not a number" + allowed;
  if (!std::isfinite(v) || errno == ERANGE) return "'" + text + "' is not a finite number" + allowed;
  if (r.integer && v != std::floor(v)) return "'" + text + "' is not a whole number" + allowed;
  if (v < r.lo || (r.lo_open && v == r.lo) || v > r.hi) return "'" + text + "' is out of range" + allowed;
  if (value) *value = v;
  return {};
}

}  // namespace amb::cli
