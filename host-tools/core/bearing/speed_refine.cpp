#include "host-tools/core/bearing/speed_refine.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host-tools/core/bearing/line_family.hpp"

namespace amb::host::bearing {

SpeedRefinement refine_speed(const std::vector<double>& magnitude, double df_hz, double nominal_hz, double range,
                             int harmonics, double false_alarm, const std::vector<double>& excluded_orders,
                             double excluded_tolerance) {
  if (!(df_hz > 0) || !(nominal_hz > 0) || !(range > 0 && range < 0.5) || harmonics < 1 ||
      !(false_alarm > 0 && false_alarm < 1))
    throw std::invalid_argument("invalid speed-refinement input");
  SpeedRefinement r;
  r.nominal_hz = nominal_hz;
  r.speed_hz = nominal_hz;
  const auto n = static_cast<long>(magnitude.size());
  const long fw = std::max(8L, std::lround(5.0 / df_hz));
  // Harmonics that fit below the spectrum's end with their floor window.
  int h_max = harmonics;
  while (h_max >= 1 && std::lround(h_max * nominal_hz * (1 + range) / df_hz) + fw >= n) --h_max;
  if (h_max < 1) return r;
  std::vector<bool> used(static_cast<size_t>(h_max + 1), true);
  for (int h = 1; h <= h_max; ++h)
    for (double o : excluded_orders)
      if (o > 0 && std::abs(h - o) <= excluded_tolerance * o) used[static_cast<size_t>(h)] = false;
  for (int h = 1; h <= h_max; ++h) r.harmonics_used += used[static_cast<size_t>(h)] ? 1 : 0;
  if (r.harmonics_used < 2 || !used[1]) return r;
  // Floor per harmonic: median around the nominal position, the search range excluded.
  std::vector<double> floor(static_cast<size_t>(h_max + 1), 0.0), win;
  for (int h = 1; h <= h_max; ++h) {
    const long c = std::lround(h * nominal_hz / df_hz);
    const long w = std::lround(h * nominal_hz * range / df_hz) + 2;
    win.clear();
    for (long k = std::max(1L, c - w - fw); k <= std::min(n - 1, c + w + fw); ++k)
      if (std::abs(k - c) > w) win.push_back(magnitude[static_cast<size_t>(k)]);
    auto mid = win.begin() + static_cast<long>(win.size() / 2);
    std::nth_element(win.begin(), mid, win.end());
    floor[static_cast<size_t>(h)] = *mid;
  }
  // Grid: the top harmonic moves a quarter bin per step.
  const double step = 0.25 * df_hz / h_max;
  const long steps = std::lround(range * nominal_hz / step);
  double best = 0.0;
  double best_f = nominal_hz;
  for (long d = -steps; d <= steps; ++d) {
    const double f = nominal_hz + static_cast<double>(d) * step;
    double x = 0.0;
    for (int h = 1; h <= h_max; ++h) {
      if (!used[static_cast<size_t>(h)]) continue;
      const long c = std::lround(h * f / df_hz);
      const double ratio = floor[static_cast<size_t>(h)] > 0 ? magnitude[static_cast<size_t>(c)] / floor[static_cast<size_t>(h)] : 0.0;
      const double q = std::exp2(-ratio * ratio);
      x += -2.0 * std::log(std::max(q, 1e-300));
    }
    const double lp = log_chi2_sf_even(x, r.harmonics_used);
    if (lp < best) {
      best = lp;
      best_f = f;
    }
  }
  // Independent comb positions: the fundamental's search range in bins.
  const double trials = std::max(1.0, 2.0 * range * nominal_hz / df_hz);
  r.log10_p = std::min(0.0, best / std::log(10.0) + std::log10(trials));
  bool first_present = false;
  for (int h = 1; h <= h_max; ++h) {
    if (!used[static_cast<size_t>(h)]) continue;
    const long c = std::lround(h * best_f / df_hz);
    const double ratio = floor[static_cast<size_t>(h)] > 0 ? magnitude[static_cast<size_t>(c)] / floor[static_cast<size_t>(h)] : 0.0;
    const bool present = std::exp2(-ratio * ratio) < 0.01;
    r.harmonics_present += present ? 1 : 0;
    if (h == 1) first_present = present;
  }
  // A shaft comb has its 1x line and at least one harmonic; a comb of another line family that
  // happens to align with a few multiples (ball-pass harmonics) lacks the 1x.
  if (r.log10_p < std::log10(false_alarm) && first_present && r.harmonics_present >= 2) {
    r.refined = true;
    r.speed_hz = best_f;
  }
  return r;
}

}  // namespace amb::host::bearing
