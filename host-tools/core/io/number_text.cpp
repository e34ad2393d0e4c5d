#include "host-tools/core/io/number_text.hpp"

#include <cstdarg>
#include <cstdio>

namespace amb::host::io {

std::string printf_text(const char* printf_format, ...) {
  va_list args;
  va_start(args, printf_format);
  va_list again;
  va_copy(again, args);
  char small[128];
  // First pass into a stack buffer: most numbers fit; the exact length comes back either way.
  const int n = std::vsnprintf(small, sizeof small, printf_format, args);
  va_end(args);
  std::string out;
  if (n < 0) {
    va_end(again);
    return out;  // an encoding error: no text rather than half of it
  }
  if (static_cast<size_t>(n) < sizeof small) {
    out.assign(small, static_cast<size_t>(n));
  } else {
    out.resize(static_cast<size_t>(n));
    std::vsnprintf(out.data(), out.size() + 1, printf_format, again);
  }
  va_end(again);
  return out;
}

std::string exact_text(double v) { return printf_text("%.17g", v); }

}  // namespace amb::host::io
