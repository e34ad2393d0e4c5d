#include "host-tools/core/fit/drop_cost.hpp"

#include <Eigen/Dense>

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

namespace {

// Least-squares line of v over indices [i0, n): slope and value at index n - 1.
bool ls_line(const std::vector<double>& v, size_t i0, double period_s, double& slope, double& end_value) {
  const size_t n = v.size();
  if (n < i0 + 3) return false;
  double st = 0.0, sw = 0.0, stt = 0.0, stw = 0.0;
  const double m = static_cast<double>(n - i0);
  for (size_t i = i0; i < n; ++i) {
    const double t = static_cast<double>(i) * period_s;
    st += t;
    sw += v[i];
    stt += t * t;
    stw += t * v[i];
  }
  const double den = m * stt - st * st;
  if (!(den > 0.0)) return false;
  slope = (m * stw - st * sw) / den;
  const double mean_t = st / m, mean_w = sw / m;
  end_value = mean_w + slope * (static_cast<double>(n - 1) * period_s - mean_t);
  return true;
}

}  // namespace

LockInFeatures lock_in_features(const std::array<model::drop::RubbingResult, 2>& r, const std::array<std::vector<double>, 2>& x,
                                const std::array<std::vector<double>, 2>& y, const std::array<double, 2>& clearance_m,
                                const std::vector<double>& speed_rad_s, double period_s, double margin_s, double min_s,
                                double start_override_s) {
  namespace md = model::drop;
  LockInFeatures f;
  const size_t n = r[0].state.size();
  if (n == 0 || r[1].state.size() != n) return f;
  // Onset of each bearing's longest backward run; the sustained whirl starts a margin after
  // the latest one (the state is flagged from a centred slope window, so up to half a window
  // early, and the lock-in transient follows).
  double start = -1.0;
  for (size_t k = 0; k < 2; ++k) {
    size_t best_len = 0, best_start = 0, run = 0;
    for (size_t i = 0; i < n; ++i) {
      run = r[k].state[i] == md::RubState::backward ? run + 1 : 0;
      if (run > best_len) {
        best_len = run;
        best_start = i + 1 - run;
      }
    }
    if (static_cast<double>(best_len) * period_s >= margin_s + min_s)
      start = std::max(start, static_cast<double>(best_start) * period_s + margin_s);
  }
  f.own = start >= 0.0;
  if (!f.own) start = start_override_s;
  if (start < 0.0) return f;
  const size_t i0 = static_cast<size_t>(std::lround(start / period_s));
  if (static_cast<double>(n - std::min(n, i0)) * period_s < min_s) return f;
  f.start_s = start;
  f.valid = true;
  double slope = 0.0, level = 0.0;
  if (ls_line(speed_rad_s, i0, period_s, slope, level)) {
    f.spin_down_rad_s2 = -slope;
    f.speed_level_rad_s = level;
  }
  for (size_t k = 0; k < 2; ++k) {
    // Radius about the whirl's own centre (algebraic least-squares circle through its contact
    // points, exact for a circle whatever part of a turn the window holds), not the rig's
    // nominal bearing centre: an offset bearing (or a sensor zero error) must not read as
    // penetration. x^2 + y^2 + D x + E y + F = 0, centre (-D/2, -E/2).
    double cx = 0.0, cy = 0.0;
    {
      Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
      Eigen::Vector3d atb = Eigen::Vector3d::Zero();
      size_t nc = 0;
      for (size_t i = i0; i < n; ++i)
        if (r[k].contact[i] != 0) {
          const Eigen::Vector3d row(x[k][i], y[k][i], 1.0);
          ata += row * row.transpose();
          atb -= row * (x[k][i] * x[k][i] + y[k][i] * y[k][i]);
          ++nc;
        }
      if (nc >= 3) {
        const Eigen::Vector3d def = ata.ldlt().solve(atb);
        if (def.allFinite()) {
          cx = -0.5 * def(0);
          cy = -0.5 * def(1);
        }
      }
    }
    size_t backward = 0, in_contact = 0;
    double acc = 0.0, pen = 0.0;
    for (size_t i = i0; i < n; ++i) {
      if (r[k].state[i] == md::RubState::backward) ++backward;
      if (r[k].contact[i] == 0) continue;
      const double rad = std::hypot(x[k][i] - cx, y[k][i] - cy);
      ++in_contact;
      acc += rad * r[k].slope_rad_s[i] * r[k].slope_rad_s[i];
      pen += rad - clearance_m[k];
    }
    f.whirling[k] = 2 * backward >= n - i0 && in_contact > 0;
    if (f.whirling[k]) {
      f.centripetal_m_s2[k] = acc / static_cast<double>(in_contact);
      f.penetration_m[k] = pen / static_cast<double>(in_contact);
    }
  }
  return f;
}

DropFeatures drop_features(const model::PlantParams& rig, const model::drop::SensorOrbit& view,
                           const std::vector<std::array<double, 4>>& sensor_m, const std::vector<double>& speed_rad_s,
                           double period_s, double spin_sign, const model::drop::RubbingOptions& rubbing,
                           double lock_in_margin_s, double lock_in_min_s, double lock_in_start_override_s) {
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
  std::array<model::drop::RubbingResult, 2> rr;
  for (size_t k = 0; k < 2; ++k) {
    rr[k] = model::drop::classify_rubbing(x[k], y[k], period_s, rig.aux[k].clearance_m, spin_sign, 0, rubbing);
    f.rubbing[k] = rr[k].durations;
    f.whirl[k] = whirl_summary(rr[k], period_s, spin_sign);
  }
  f.lock_in = lock_in_features(rr, x, y, {rig.aux[0].clearance_m, rig.aux[1].clearance_m}, speed_rad_s, period_s, lock_in_margin_s,
                               lock_in_min_s, lock_in_start_override_s);
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
  // Backward-whirl record: the sustained whirl after lock-in replaces the lock-in-dependent terms.
  const bool backward = meas.whirl[0].direction == "backward" || meas.whirl[1].direction == "backward";
  c.lock_in = w.lock_in_features && backward && meas.lock_in.valid && meas.lock_in.own;
  if (c.lock_in) {
    const auto& a = meas.lock_in;
    const auto& b = sim.lock_in;
    const bool speed = speed0_rad_s > 0.0 && !meas.speed_rad_s.empty() && !sim.speed_rad_s.empty();
    // No sustained whirl in the simulation (not even over the record's compared part): the
    // largest differences the terms can show.
    if (speed) {
      const double s1 = 0.01 * speed0_rad_s;
      c.speed = w.lock_in_speed * (b.valid ? std::abs(b.speed_level_rad_s - a.speed_level_rad_s) / s1 : 10.0);
      c.spin_down = w.lock_in_spin_down * (b.valid ? std::abs(b.spin_down_rad_s2 - a.spin_down_rad_s2) / s1 : 10.0);
    }
    const double cap = std::log(10.0);
    for (size_t k = 0; k < 2; ++k) {
      if (!a.whirling[k] || !(a.penetration_m[k] > 0.0) || !(a.centripetal_m_s2[k] > 0.0)) continue;
      double d = cap;
      if (b.valid && b.whirling[k] && b.penetration_m[k] > 0.0 && b.centripetal_m_s2[k] > 0.0) {
        const double e = sim.contact_exponent;
        d = std::min(cap, std::abs(std::log(b.centripetal_m_s2[k] / a.centripetal_m_s2[k]) -
                                   e * std::log(b.penetration_m[k] / a.penetration_m[k])));
      }
      c.whirl += w.whirl_force * d;
    }
    for (size_t k = 0; k < 2; ++k) {
      const auto& p = meas.whirl[k];
      const auto& q = sim.whirl[k];
      c.contact += w.contact_share * std::abs(p.contact_share - q.contact_share);
      c.bounce += w.bounce * std::abs(p.bounce_rate_per_s - q.bounce_rate_per_s) / 100.0;
      c.whirl += w.lock_in_whirl_rate * std::abs(p.whirl_rate_rad_s - q.whirl_rate_rad_s) / std::max(std::abs(speed0_rad_s), 1.0);
    }
    c.total = c.rubbing + c.orbit + c.speed + c.spin_down + c.contact + c.whirl + c.bounce;
    return c;
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
