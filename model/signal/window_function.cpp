#include "model/signal/window_function.hpp"

#include <cmath>
#include <numbers>

namespace amb::model::signal {

std::string_view window_name(WindowType type) {
  switch (type) {
    case WindowType::kRectangular: return "rectangular";
    case WindowType::kHann: return "hann";
    case WindowType::kHamming: return "hamming";
    case WindowType::kBlackman: return "blackman";
  }
  return "unknown";
}

bool parse_window(std::string_view name, WindowType& type) {
  for (WindowType t : {WindowType::kRectangular, WindowType::kHann, WindowType::kHamming,
                       WindowType::kBlackman}) {
    if (name == window_name(t)) {
      type = t;
      return true;
    }
  }
  return false;
}

void fill_window(WindowType type, std::span<double> w) {
  const size_t n = w.size();
  if (n == 0) return;
  if (n == 1) {
    w[0] = 1.0;
    return;
  }
  const double step = 2.0 * std::numbers::pi / static_cast<double>(n - 1);
  for (size_t i = 0; i < n; ++i) {
    const double x = step * static_cast<double>(i);
    switch (type) {
      case WindowType::kRectangular: w[i] = 1.0; break;
      case WindowType::kHann: w[i] = 0.5 - 0.5 * std::cos(x); break;
      case WindowType::kHamming: w[i] = 0.54 - 0.46 * std::cos(x); break;
      case WindowType::kBlackman:
        w[i] = 0.42 - 0.5 * std::cos(x) + 0.08 * std::cos(2.0 * x);
        break;
    }
  }
}

double main_lobe_half_width_bins(WindowType type) {
  switch (type) {
    case WindowType::kRectangular: return 1.0;
    case WindowType::kHann: return 2.0;
    case WindowType::kHamming: return 2.0;
    case WindowType::kBlackman: return 3.0;
  }
  return 2.0;
}

}  // namespace amb::model::signal
