#include "model/plant/aux_contact.hpp"

#include <algorithm>
#include <cmath>

namespace amb::model {

ContactResult aux_contact(const AuxBearingParams& b, const ContactState& s, double h, double eps, double hertz_exponent,
                          double hertz_reference_m) {
  ContactResult out;
  const double dx = s.x_m - b.centre_offset_x_m, dy = s.y_m - b.centre_offset_y_m;
  const double r = std::hypot(dx, dy);
  const double pen = r - b.clearance_m;
  if (pen <= 0.0 || r <= 0.0) return out;
  out.penetration_m = pen;
  const double nx = dx / r, ny = dy / r;     // outward normal (rotor towards the ring)
  const double tx = -ny, ty = nx;            // t = z x n: direction of positive spin at the contact
  const double vn = s.vx_m_s * nx + s.vy_m_s * ny;
  // Kelvin-Voigt penalty; clipped at zero so the damper never pulls the rotor back in.
  // Elastic part: linear, or K d^e with dF/dd = k at the reference penetration.
  const double elastic = hertz_exponent == 1.0
                             ? b.contact_stiffness_n_per_m * pen
                             : b.contact_stiffness_n_per_m / (hertz_exponent * std::pow(hertz_reference_m, hertz_exponent - 1.0)) *
                                   std::pow(pen, hertz_exponent);
  const double fn = std::max(0.0, elastic + b.contact_damping_n_s_per_m * vn);
  out.normal_n = fn;
  const double ring_radius = b.collar_radius_m + b.clearance_m;
  const double slip0 = s.vx_m_s * tx + s.vy_m_s * ty + s.spin_rad_s * b.collar_radius_m -
                       s.ring_rad_s * ring_radius;
  double ft = 0.0, slip = slip0;
  const double cap = b.friction_coefficient * fn;
  if (cap > 0.0) {
    // Slip-velocity change per unit tangential force over the step (collar lateral motion,
    // rotor spin and ring spin all respond).
    const double w = h * (s.lateral_inv_mass_1_per_kg +
                          b.collar_radius_m * b.collar_radius_m / std::max(s.spin_inertia_kg_m2, 1e-12) +
                          ring_radius * ring_radius / std::max(b.ring_inertia_kg_m2, 1e-12));
    // g(F) = F + cap phi(slip0 + w F) is strictly increasing with its root in [-cap, cap]:
    // safeguarded Newton, a fixed maximum of iterations.
    double lo = -cap, hi = cap;
    ft = -cap * regularised_sign(slip0, eps);
    for (int it = 0; it < 30; ++it) {
      const double v = slip0 + w * ft;
      const double den = std::sqrt(v * v + eps * eps);
      const double g = ft + cap * v / den;
      if (g > 0.0) hi = ft; else lo = ft;
      const double dg = 1.0 + cap * w * eps * eps / (den * den * den);
      double next = ft - g / dg;
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - ft) <= 1e-12 * cap + 1e-15) { ft = next; break; }
      ft = next;
    }
    slip = slip0 + w * ft;
  }
  out.friction_n = ft;
  out.slip_end_m_s = slip;
  out.fx_n = -fn * nx + ft * tx;
  out.fy_n = -fn * ny + ft * ty;
  out.spin_torque_n_m = ft * b.collar_radius_m;
  out.ring_torque_n_m = -ft * ring_radius;
  out.friction_power_w = -ft * slip;
  return out;
}

}  // namespace amb::model
