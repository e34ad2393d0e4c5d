#include "firmware/bearing/bearing_task.hpp"

#include <cmath>

namespace amb::fw {

namespace mb = amb::model::bearing;

bool BearingTask::configure(const BearingTaskConfig& c) {
  configured_ = false;
  if (!c.bearing.valid() || c.bearing.ball_count > mb::k_max_balls) return false;
  if (!(c.radial_clearance_m >= 0) || !(c.min_speed_hz > 0) || !(c.max_speed_hz > c.min_speed_hz)) return false;
  if (!(c.aux_radial_clearance_m > 0) || !(c.aux_contact_constant_n_per_m1p5 >= 0) ||
      !(c.aux_dynamic_load_rating_n >= 0) || !(c.aux_spin_speed_hz >= 0) || !(c.hertz_constant_n_per_m1p5 >= 0))
    return false;
  cfg_ = c;
  kb_nom_ = c.hertz_constant_n_per_m1p5 > 0 ? c.hertz_constant_n_per_m1p5 : mb::nominal_hertz_constant(c.bearing);
  orders_ = mb::defect_orders(c.bearing);
  eta_ = 1.0;
  if (!rebuild_law()) return false;
  configured_ = true;
  return true;
}

bool BearingTask::rebuild_law() noexcept {
  mb::ContactLawParams p;
  p.geometry = cfg_.bearing;
  p.hertz_constant_n_per_m1p5 = eta_ * kb_nom_;
  p.radial_clearance_m = cfg_.radial_clearance_m;
  return law_.configure(p);  // fixed-size tables: no allocation
}

DefectUpdate BearingTask::update_speed(double speed_hz) noexcept {
  DefectUpdate u;
  if (!configured_ || !(speed_hz >= cfg_.min_speed_hz) || !(speed_hz <= cfg_.max_speed_hz)) {
    ++counters_.rejected_speeds;
    return u;
  }
  u.valid = true;
  u.shaft_hz = speed_hz;
  u.ftf_hz = orders_.ftf * speed_hz;
  u.bpfo_hz = orders_.bpfo * speed_hz;
  u.bpfi_hz = orders_.bpfi * speed_hz;
  u.bsf_hz = orders_.bsf * speed_hz;
  last_defects_ = u;
  return u;
}

bool BearingTask::set_stiffness_scale(double eta) noexcept {
  if (!configured_ || !(eta >= 0.05 && eta <= 20.0)) {
    ++counters_.rejected_stiffness_updates;
    return false;
  }
  const double old = eta_;
  eta_ = eta;
  if (!rebuild_law()) {
    eta_ = old;
    rebuild_law();
    ++counters_.rejected_stiffness_updates;
    return false;
  }
  return true;
}

StiffnessUpdate BearingTask::update_stiffness(double load_n, double cage_angle_rad) noexcept {
  StiffnessUpdate u;
  u.eta = eta_;
  if (!configured_ || !(load_n > 0) || !std::isfinite(load_n)) {
    ++counters_.rejected_stiffness_updates;
    return u;
  }
  // Static equilibrium along +x: find d with F_x(d) = load (F_x is monotonic in d beyond the
  // clearance). Bracket: [clearance, clearance + deflection of one ball carrying all the load].
  double lo = cfg_.radial_clearance_m;
  double hi = lo + std::cbrt((load_n / (eta_ * kb_nom_)) * (load_n / (eta_ * kb_nom_))) * 2.0 + 1e-9;
  const double cage_ratio = law_.cage_ratio();
  const double shaft_angle = cage_ratio > 0 ? cage_angle_rad / cage_ratio : 0.0;
  auto fx = [&](double d) { return law_.force(d, 0.0, shaft_angle).fx_n; };
  for (int i = 0; i < 8 && fx(hi) < load_n; ++i) hi *= 2.0;  // bounded widening
  if (fx(hi) < load_n) {
    ++counters_.rejected_stiffness_updates;
    return u;
  }
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fx(mid) < load_n ? lo : hi) = mid;
  }
  const double d = 0.5 * (lo + hi);
  const auto f = law_.force(d, 0.0, shaft_angle);
  u.valid = true;
  u.deflection_m = d;
  u.stiffness_n_per_m = std::hypot(f.fx_n, f.fy_n) / d;  // seed 003 eq. 8: F_r / r
  last_stiffness_ = u;
  return u;
}

void BearingTask::estimate_drop_load(std::span<const double> x_m, std::span<const double> y_m, double dt_s,
                                     DropLoadEstimate& out) noexcept {
  estimate_drop_load_at(x_m, y_m, dt_s, cfg_.aux_radial_clearance_m, cfg_.aux_spin_speed_hz, out);
}

void BearingTask::estimate_drop_load_at(std::span<const double> x_m, std::span<const double> y_m, double dt_s,
                                        double clearance_m, double spin_hz, DropLoadEstimate& out) noexcept {
  out = DropLoadEstimate{};
  if (!configured_ || x_m.size() != y_m.size() || x_m.empty() || !(dt_s > 0) ||
      !(cfg_.aux_contact_constant_n_per_m1p5 > 0) || !(clearance_m > 0) || !(spin_hz >= 0)) {
    ++counters_.rejected_drops;
    return;
  }
  const double k = cfg_.aux_contact_constant_n_per_m1p5;
  const double c = clearance_m;
  for (size_t i = 0; i < x_m.size(); ++i) {
    const double x = x_m[i], y = y_m[i];
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    const double pen = std::hypot(x, y) - c;
    if (pen <= 0) continue;
    const double f = k * pen * std::sqrt(pen);
    double ang = std::atan2(y, x) * (180.0 / M_PI);
    if (ang < 0) ang += 360.0;
    auto bin = static_cast<int>(ang);
    if (bin >= DropLoadEstimate::k_bins) bin = 0;
    const auto b = static_cast<size_t>(bin);
    out.impulse_n_s[b] += f * dt_s;
    out.damage_n3_s[b] += f * f * f * dt_s;
    ++out.samples_in_contact;
    if (f > out.peak_force_n) {
      out.peak_force_n = f;
      out.peak_angle_deg = ang;
    }
  }
  for (double d : out.damage_n3_s) out.damage_total_n3_s += d;
  out.contact_time_s = out.samples_in_contact * dt_s;
  if (cfg_.aux_dynamic_load_rating_n > 0 && spin_hz > 0) {
    const double c3 = cfg_.aux_dynamic_load_rating_n * cfg_.aux_dynamic_load_rating_n * cfg_.aux_dynamic_load_rating_n;
    out.miner_fraction = out.damage_total_n3_s / c3 * spin_hz / 1e6;
  }
  out.valid = true;
}

}  // namespace amb::fw
