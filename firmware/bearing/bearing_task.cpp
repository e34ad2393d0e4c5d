#include "firmware/bearing/bearing_task.hpp"

#include <algorithm>
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
  if (!(c.rotor_mass_kg >= 0) || !(c.rotor_transverse_inertia_kg_m2 >= 0) || !std::isfinite(c.rotor_cm_axial_m) ||
      !(c.aux_axial_m[1] != c.aux_axial_m[0]) || !std::isfinite(c.aux_axial_m[0]) || !std::isfinite(c.aux_axial_m[1]) ||
      !(c.gravity_m_s2 >= 0) || !(c.contact_fraction > 0 && c.contact_fraction <= 1) || !(c.accel_half_span_s > 0))
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

double BearingTask::impact_mass_kg(size_t bearing) const noexcept {
  const double za = cfg_.aux_axial_m[0], zb = cfg_.aux_axial_m[1], zg = cfg_.rotor_cm_axial_m;
  const double share = bearing == 0 ? (zb - zg) / (zb - za) : (zg - za) / (zb - za);
  return cfg_.rotor_mass_kg * std::clamp(share, 0.0, 1.0);
}

void BearingTask::estimate_drop_loads(const DropOrbit& in, std::array<DropLoadEstimate, 2>& out) noexcept {
  out[0] = DropLoadEstimate{};
  out[1] = DropLoadEstimate{};
  const size_t n = in.x_m[0].size();
  const double spin = in.spin_hz >= 0 ? in.spin_hz : cfg_.aux_spin_speed_hz;
  std::array<double, 2> c{};
  for (size_t k = 0; k < 2; ++k) c[k] = in.clearance_m[k] > 0 ? in.clearance_m[k] : cfg_.aux_radial_clearance_m;
  const bool sizes_ok = in.x_m[1].size() == n && in.y_m[0].size() == n && in.y_m[1].size() == n;
  if (!configured_ || !sizes_ok || n == 0 || !(in.dt_s > 0) || !(cfg_.rotor_mass_kg > 0) ||
      !(cfg_.rotor_transverse_inertia_kg_m2 > 0) || !(c[0] > 0) || !(c[1] > 0) || !std::isfinite(spin)) {
    ++counters_.rejected_drops;
    return;
  }
  const double m = cfg_.rotor_mass_kg, inertia = cfg_.rotor_transverse_inertia_kg_m2;
  const double za = cfg_.aux_axial_m[0], zb = cfg_.aux_axial_m[1], zg = cfg_.rotor_cm_axial_m;
  const double g = cfg_.gravity_m_s2;
  const double kh = cfg_.aux_contact_constant_n_per_m1p5;
  const auto h = static_cast<size_t>(std::max(1.0, std::round(cfg_.accel_half_span_s / in.dt_s)));
  const double hdt = static_cast<double>(h) * in.dt_s;
  const std::array<double, 2> m_k{impact_mass_kg(0), impact_mass_kg(1)};
  auto at = [&](size_t k, size_t i, double& x, double& y) {
    x = in.x_m[k][i];
    y = in.y_m[k][i];
    return std::isfinite(x) && std::isfinite(y);
  };
  // A contact under way in the window's first sample is not an impact of this window.
  auto in_contact_at = [&](size_t k, size_t i) {
    double x = 0, y = 0;
    return at(k, i, x, y) && std::hypot(x, y) >= cfg_.contact_fraction * c[k];
  };
  std::array<bool, 2> was_in{n > h && in_contact_at(0, h - 1), n > h && in_contact_at(1, h - 1)};
  for (size_t i = h; i + h < n; ++i) {
    // Accelerations at both planes (second difference over +-h samples).
    std::array<double, 2> ax{}, ay{}, px{}, py{}, vr{};
    bool ok = true;
    for (size_t k = 0; k < 2 && ok; ++k) {
      double x0 = 0, y0 = 0, x1 = 0, y1 = 0, x2 = 0, y2 = 0;
      ok = at(k, i - h, x0, y0) && at(k, i, x1, y1) && at(k, i + h, x2, y2);
      ax[k] = (x2 - 2.0 * x1 + x0) / (hdt * hdt);
      ay[k] = (y2 - 2.0 * y1 + y0) / (hdt * hdt);
      vr[k] = (std::hypot(x1, y1) - std::hypot(x0, y0)) / hdt;
      px[k] = x1;
      py[k] = y1;
    }
    if (!ok) {
      was_in = {false, false};
      continue;
    }
    // Rigid rotor: a(z) = a_G + alpha (z - z_G). Sum of the bearing forces S = m (a_G - g),
    // their moment about G  M = I alpha  =>  F_B = (M - (z_A - z_G) S) / (z_B - z_A), F_A = S - F_B.
    const double alx = (ax[1] - ax[0]) / (zb - za), aly = (ay[1] - ay[0]) / (zb - za);
    const double agx = ax[0] + alx * (zg - za), agy = ay[0] + aly * (zg - za);
    const double sx = m * agx, sy = m * (agy + g);
    const double fbx = (inertia * alx - (za - zg) * sx) / (zb - za);
    const double fby = (inertia * aly - (za - zg) * sy) / (zb - za);
    const std::array<double, 2> fx{sx - fbx, fbx}, fy{sy - fby, fby};
    for (size_t k = 0; k < 2; ++k) {
      DropLoadEstimate& e = out[k];
      const double r = std::hypot(px[k], py[k]);
      const bool in_contact = r >= cfg_.contact_fraction * c[k] && r > 0;
      if (!in_contact) {
        was_in[k] = false;
        continue;
      }
      const double nx = px[k] / r, ny = py[k] / r;
      double f = std::max(0.0, -(fx[k] * nx + fy[k] * ny));  // inward push of the bearing
      if (!was_in[k]) {
        ++e.impacts;
        const double v = vr[k];  // outward approach speed (radial: a whirl on the circle has none)
        if (kh > 0 && v > 0 && m_k[k] > 0) {
          const double f_imp = std::pow(kh, 0.4) * std::pow(1.25 * m_k[k] * v * v, 0.6);
          e.peak_impact_force_n = std::max(e.peak_impact_force_n, f_imp);
          f = std::max(f, f_imp);
        }
      }
      was_in[k] = true;
      double ang = std::atan2(py[k], px[k]) * (180.0 / M_PI);
      if (ang < 0) ang += 360.0;
      auto bin = static_cast<int>(ang);
      if (bin >= DropLoadEstimate::k_bins) bin = 0;
      const auto b = static_cast<size_t>(bin);
      e.impulse_n_s[b] += f * in.dt_s;
      e.damage_n3_s[b] += f * f * f * in.dt_s;
      ++e.samples_in_contact;
      if (f > e.peak_force_n) {
        e.peak_force_n = f;
        e.peak_angle_deg = ang;
      }
    }
  }
  for (DropLoadEstimate& e : out) {
    for (double d : e.damage_n3_s) e.damage_total_n3_s += d;
    e.contact_time_s = e.samples_in_contact * in.dt_s;
    if (cfg_.aux_dynamic_load_rating_n > 0 && spin > 0) {
      const double c3 = cfg_.aux_dynamic_load_rating_n * cfg_.aux_dynamic_load_rating_n * cfg_.aux_dynamic_load_rating_n;
      e.miner_fraction = e.damage_total_n3_s / c3 * spin / 1e6;
    }
    e.valid = true;
  }
}

}  // namespace amb::fw
