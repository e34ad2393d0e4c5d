#include "host-tools/core/fit/drop_cost.hpp"

#include <algorithm>
#include <cmath>

namespace amb::host::fit {

WhirlSummary whirl_summary(const model::drop::RubbingResult& r, double period_s, double spin_sign) {
  namespace md = model::drop;
  WhirlSummary w;
  const size_t n = r.state.size();
  if (n == 0 || r.first_contact < 0) return w;
  size_t in_contact = 0, onsets = 0;
  double rate_sum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    if (r.contact[i] == 0) continue;
    ++in_contact;
    if (i == 0 || r.contact[i - 1] == 0) ++onsets;
    rate_sum += r.slope_rad_s[i] * spin_sign;
  }
  w.contact_share = static_cast<double>(in_contact) / static_cast<double>(n);
  w.whirl_rate_rad_s = in_contact > 0 ? rate_sum / static_cast<double>(in_contact) : 0.0;
  w.bounce_rate_per_s = static_cast<double>(onsets) / (static_cast<double>(n) * period_s);
  const auto& d = r.durations;
  md::RubState dominant = md::RubState::swing;
  double longest = d.swing_s;
  if (d.forward_s > longest) { dominant = md::RubState::forward; longest = d.forward_s; }
  if (d.backward_s > longest) { dominant = md::RubState::backward; longest = d.backward_s; }
  if (longest <= 0.0) return w;
  w.direction = dominant == md::RubState::swing ? "bouncing" : dominant == md::RubState::forward ? "forward" : "backward";
  double f_sum = 0.0;
  size_t f_n = 0;
  for (size_t i = 0; i < n; ++i) {
    if (r.state[i] != dominant) continue;
    if (w.onset_s < 0.0) w.onset_s = static_cast<double>(i) * period_s;
    f_sum += std::abs(r.slope_rad_s[i]);
    ++f_n;
  }
  w.frequency_hz = f_n > 0 ? f_sum / static_cast<double>(f_n) / (2.0 * M_PI) : 0.0;
  return w;
}

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
  for (size_t k = 0; k < 2; ++k) {
    const auto r = model::drop::classify_rubbing(x[k], y[k], period_s, rig.aux[k].clearance_m, spin_sign, 0, rubbing);
    f.rubbing[k] = r.durations;
    f.whirl[k] = whirl_summary(r, period_s, spin_sign);
  }
  if (speed_rad_s.size() > 2) {
    // Least-squares slope of the speed over the window.
    const double n = static_cast<double>(speed_rad_s.size());
    double st = 0.0, sw = 0.0, stt = 0.0, stw = 0.0;
    for (size_t i = 0; i < speed_rad_s.size(); ++i) {
      const double t = static_cast<double>(i) * period_s;
      st += t;
      sw += speed_rad_s[i];
      stt += t * t;
      stw += t * speed_rad_s[i];
    }
    f.spin_down_rad_s2 = -(n * stw - st * sw) / (n * stt - st * st);
  }
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
  if (speed0_rad_s > 0.0 && !meas.speed_rad_s.empty() && !sim.speed_rad_s.empty())
    c.spin_down = w.spin_down * std::abs(sim.spin_down_rad_s2 - meas.spin_down_rad_s2) / (0.01 * speed0_rad_s);
  const double spin = std::max(std::abs(speed0_rad_s), 1.0);
  for (size_t k = 0; k < 2; ++k) {
    const auto& a = meas.whirl[k];
    const auto& b = sim.whirl[k];
    c.contact += w.contact_share * std::abs(a.contact_share - b.contact_share);
    c.whirl += w.whirl * std::abs(a.whirl_rate_rad_s - b.whirl_rate_rad_s) / spin;
    c.bounce += w.bounce * std::abs(a.bounce_rate_per_s - b.bounce_rate_per_s) / 100.0;
  }
  c.total = c.rubbing + c.orbit + c.speed + c.spin_down + c.contact + c.whirl + c.bounce;
  return c;
}

}  // namespace amb::host::fit
