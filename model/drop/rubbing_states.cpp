#include "model/drop/rubbing_states.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace amb::model::drop {

std::string RubbingOptions::check() const {
  if (!(contact_radius_fraction > 0.0 && contact_radius_fraction <= 1.5)) return "contact_radius_fraction must be in (0, 1.5]";
  if (!(slope_window_s > 0.0)) return "slope_window_s must be > 0";
  if (!(rub_slope_rad_s > 0.0)) return "rub_slope_rad_s must be > 0";
  if (!(rub_contact_fraction > 0.0 && rub_contact_fraction <= 1.0)) return "rub_contact_fraction must be in (0, 1]";
  return {};
}

const char* to_string(RubState s) {
  switch (s) {
    case RubState::none: return "none";
    case RubState::swing: return "swing";
    case RubState::forward: return "forward";
    case RubState::backward: return "backward";
  }
  return "?";
}

RubbingResult classify_rubbing(const std::vector<double>& x_m, const std::vector<double>& y_m, double period_s,
                               double clearance_m, double spin_sign, int first, const RubbingOptions& o) {
  if (x_m.size() != y_m.size()) throw std::invalid_argument("classify_rubbing: x and y differ in length");
  if (!(period_s > 0.0) || !(clearance_m > 0.0)) throw std::invalid_argument("classify_rubbing: period and clearance must be > 0");
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument("classify_rubbing: " + e);
  const int n = static_cast<int>(x_m.size());
  first = std::clamp(first, 0, n);
  RubbingResult r;
  r.state.assign(static_cast<size_t>(n), RubState::none);
  r.angle_rad.assign(static_cast<size_t>(n), 0.0);
  r.slope_rad_s.assign(static_cast<size_t>(n), 0.0);
  r.contact.assign(static_cast<size_t>(n), 0);
  if (n == 0) return r;

  // Unwrapped whirl angle and the contact flags; prefix sums for windowed contact share.
  std::vector<int> contact_sum(static_cast<size_t>(n) + 1, 0);
  double prev = std::atan2(y_m[0], x_m[0]), unwrapped = prev;
  const double r_contact = o.contact_radius_fraction * clearance_m;
  for (int i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(i);
    const double a = std::atan2(y_m[k], x_m[k]);
    double d = a - prev;
    d -= 2.0 * M_PI * std::round(d / (2.0 * M_PI));
    unwrapped += i == 0 ? 0.0 : d;
    prev = a;
    r.angle_rad[k] = unwrapped;
    r.contact[k] = std::hypot(x_m[k], y_m[k]) >= r_contact ? 1 : 0;
    contact_sum[k + 1] = contact_sum[k] + r.contact[k];
    if (r.first_contact < 0 && i >= first && r.contact[k]) r.first_contact = i;
  }
  if (r.first_contact < 0) return r;

  const int half = std::max(1, static_cast<int>(std::lround(0.5 * o.slope_window_s / period_s)));
  const double sgn = spin_sign >= 0.0 ? 1.0 : -1.0;
  for (int i = r.first_contact; i < n; ++i) {
    const int lo = std::max(r.first_contact, i - half), hi = std::min(n - 1, i + half);
    const size_t k = static_cast<size_t>(i);
    if (hi <= lo) {
      r.state[k] = RubState::swing;
      continue;
    }
    const double slope = (r.angle_rad[static_cast<size_t>(hi)] - r.angle_rad[static_cast<size_t>(lo)]) / ((hi - lo) * period_s);
    r.slope_rad_s[k] = slope;
    const double share = static_cast<double>(contact_sum[static_cast<size_t>(hi) + 1] - contact_sum[static_cast<size_t>(lo)]) /
                         static_cast<double>(hi - lo + 1);
    RubState s = RubState::swing;
    if (share >= o.rub_contact_fraction && std::abs(slope) >= o.rub_slope_rad_s)
      s = sgn * slope > 0.0 ? RubState::forward : RubState::backward;
    r.state[k] = s;
  }
  for (int i = r.first_contact; i < n; ++i) {
    const RubState s = r.state[static_cast<size_t>(i)];
    if (s == RubState::swing) r.durations.swing_s += period_s;
    if (s == RubState::forward) r.durations.forward_s += period_s;
    if (s == RubState::backward) r.durations.backward_s += period_s;
  }
  return r;
}

}  // namespace amb::model::drop
