#include "host-tools/core/wear/load_map.hpp"

#include <algorithm>
#include <cmath>

namespace amb::host::wear {

int load_bin(double angle_deg) {
  double a = std::fmod(angle_deg, 360.0);
  if (a < 0.0) a += 360.0;
  return std::clamp(static_cast<int>(std::floor(a)), 0, fw::k_load_bins - 1);
}

std::array<BearingEventLoad, 2> event_load(const std::vector<model::drop::StepContact>& steps) {
  std::array<BearingEventLoad, 2> out{};
  std::array<double, 2> prev_angle{}, prev_t{}, turned_deg{}, turned_s{};
  std::array<bool, 2> has_prev{};
  for (const auto& c : steps)
    for (size_t b = 0; b < 2; ++b) {
      if (!c.active[b]) {
        has_prev[b] = false;
        continue;
      }
      // Whirl: angle change between consecutive closed steps (a positive spin moves the
      // contact point to decreasing polar angle, board convention).
      if (has_prev[b] && c.t_s - prev_t[b] <= 1.5 * c.h_s) {
        turned_deg[b] += std::remainder(c.angle_deg[b] - prev_angle[b], 360.0);
        turned_s[b] += c.t_s - prev_t[b];
      }
      has_prev[b] = true;
      prev_angle[b] = c.angle_deg[b];
      prev_t[b] = c.t_s;
      const double f = std::hypot(c.normal_n[b], c.friction_n[b]);
      auto& o = out[b];
      o.contact_time_s += c.h_s;
      o.friction_energy_j += c.friction_power_w[b] * c.h_s;
      if (f <= 0.0) continue;
      o.load_n[static_cast<size_t>(load_bin(c.angle_deg[b]))] += f * c.h_s / k_load_reference_period_s;
      o.peak_force_n = std::max(o.peak_force_n, f);
    }
  for (size_t b = 0; b < 2; ++b)
    if (turned_s[b] > 0.0) out[b].whirl_hz = -turned_deg[b] / 360.0 / turned_s[b];
  return out;
}

}  // namespace amb::host::wear
