#include "host-tools/core/fit/drop_cost.hpp"

#include <algorithm>
#include <cmath>

namespace amb::host::fit {

DropFeatures drop_features(const model::PlantParams& rig, const model::drop::SensorOrbit& view,
                           const std::vector<std::array<double, 4>>& sensor_m, const std::vector<double>& speed_rad_s,
                           double period_s, double spin_sign, const model::drop::RubbingOptions& rubbing) {
  DropFeatures f;
  f.period_s = period_s;
  f.speed_rad_s = speed_rad_s;
  f.plane_xy_m.reserve(sensor_m.size());
  std::array<std::vector<double>, 2> x, y;
  for (const auto& r : sensor_m) {
    const auto a = view.at_sensor_plane(r, 0), b = view.at_sensor_plane(r, 1);
    f.plane_xy_m.push_back({a[0], a[1], b[0], b[1]});
    for (int k = 0; k < 2; ++k) {
      const auto p = view.at_aux_plane(r, k);
      const auto& aux = rig.aux[static_cast<size_t>(k)];
      x[static_cast<size_t>(k)].push_back(p[0] - aux.centre_offset_x_m);
      y[static_cast<size_t>(k)].push_back(p[1] - aux.centre_offset_y_m);
    }
  }
  for (size_t k = 0; k < 2; ++k)
    f.rubbing[k] = model::drop::classify_rubbing(x[k], y[k], period_s, rig.aux[k].clearance_m, spin_sign, 0, rubbing).durations;
  return f;
}

CostBreakdown drop_cost(const DropFeatures& meas, const DropFeatures& sim, double clearance_m, double speed0_rad_s,
                        const DropCostWeights& w) {
  CostBreakdown c;
  for (size_t k = 0; k < 2; ++k) {
    c.rubbing += w.swing_per_s * std::abs(sim.rubbing[k].swing_s - meas.rubbing[k].swing_s) +
                 w.forward_per_s * std::abs(sim.rubbing[k].forward_s - meas.rubbing[k].forward_s) +
                 w.backward_per_s * std::abs(sim.rubbing[k].backward_s - meas.rubbing[k].backward_s);
  }
  size_t n = std::min(meas.plane_xy_m.size(), sim.plane_xy_m.size());
  if (meas.period_s > 0.0) n = std::min(n, static_cast<size_t>(std::lround(w.orbit_window_s / meas.period_s)));
  if (n > 0) {
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const auto& a = meas.plane_xy_m[i];
      const auto& b = sim.plane_xy_m[i];
      sum += std::hypot(a[0] - b[0], a[1] - b[1]) * std::hypot(a[0] - b[0], a[1] - b[1]) +
             std::hypot(a[2] - b[2], a[3] - b[3]) * std::hypot(a[2] - b[2], a[3] - b[3]);
    }
    c.orbit = w.orbit * std::sqrt(sum / (2.0 * static_cast<double>(n))) / clearance_m;
  }
  const size_t ns = std::min(meas.speed_rad_s.size(), sim.speed_rad_s.size());
  if (ns > 0 && speed0_rad_s > 0.0) {
    double sum = 0.0;
    for (size_t i = 0; i < ns; ++i) sum += (meas.speed_rad_s[i] - sim.speed_rad_s[i]) * (meas.speed_rad_s[i] - sim.speed_rad_s[i]);
    c.speed = w.speed * std::sqrt(sum / static_cast<double>(ns)) / (0.01 * speed0_rad_s);
  }
  c.total = c.rubbing + c.orbit + c.speed;
  return c;
}

}  // namespace amb::host::fit
