#include "firmware/control/pid_axis.hpp"

#include <algorithm>
#include <cmath>

namespace amb::fw {

double Biquad::step(double x) {
  const double y = b0 * x + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
  x2 = x1;
  x1 = x;
  y2 = y1;
  y1 = y;
  return y;
}

Biquad design_notch(const model::NotchParams& n, double fs_hz) {
  // Analog prototype H(s) = (s^2 + 2 d z w s + w^2) / (s^2 + 2 z w s + w^2), z = width/(2 f0),
  // so |H(j w0)| = d; bilinear transform with the centre frequency pre-warped.
  const double w0 = 2.0 * M_PI * n.centre_hz;
  const double k = w0 / std::tan(w0 / (2.0 * fs_hz));
  const double zeta = n.width_hz / (2.0 * n.centre_hz);
  const double k2 = k * k, w2 = w0 * w0;
  const double nb1 = 2.0 * n.depth * zeta * w0 * k, da1 = 2.0 * zeta * w0 * k;
  const double a0 = k2 + da1 + w2;
  Biquad q;
  q.b0 = (k2 + nb1 + w2) / a0;
  q.b1 = 2.0 * (w2 - k2) / a0;
  q.b2 = (k2 - nb1 + w2) / a0;
  q.a1 = 2.0 * (w2 - k2) / a0;
  q.a2 = (k2 - da1 + w2) / a0;
  return q;
}

Biquad design_lead(double zero_hz, double pole_hz, double fs_hz) {
  // s = (2 fs) (z - 1) / (z + 1) in (1 + s/wz) / (1 + s/wp).
  const double cz = 2.0 * fs_hz / (2.0 * M_PI * zero_hz), cp = 2.0 * fs_hz / (2.0 * M_PI * pole_hz);
  Biquad q;
  q.b0 = (1.0 + cz) / (1.0 + cp);
  q.b1 = (1.0 - cz) / (1.0 + cp);
  q.a1 = (1.0 - cp) / (1.0 + cp);
  return q;
}

void PidAxis::configure(const model::PidParams& p, double rate_hz, double ki_n_per_a) {
  p_ = p;
  dt_s_ = 1.0 / rate_hz;
  deriv_alpha_ = std::exp(-2.0 * M_PI * p.derivative_filter_hz * dt_s_);
  force_limit_n_ = p.current_limit_a * ki_n_per_a;
  for (int i = 0; i < p.notch_count; ++i) notch_[static_cast<size_t>(i)] = design_notch(p.notches[static_cast<size_t>(i)], rate_hz);
  has_lead_ = p.lead_zero_hz > 0.0;
  if (has_lead_) lead_ = design_lead(p.lead_zero_hz, p.lead_pole_hz, rate_hz);
  reset();
}

void PidAxis::reset() {
  integral_n_ = 0.0;
  prev_error_m_ = 0.0;
  deriv_m_s_ = 0.0;
  for (auto& n : notch_) n.reset();
  lead_.reset();
}

void PidAxis::preload_force(double force_n) {
  integral_n_ = std::clamp(-force_n, -p_.integrator_limit_n, p_.integrator_limit_n);
  // Start the notches in their steady state for that output (unit DC gain), so the preload
  // reaches the actuators at once instead of through the filters' start-up transient.
  const double u0 = -integral_n_;
  for (auto& n : notch_) n.x1 = n.x2 = n.y1 = n.y2 = u0;
  lead_.x1 = lead_.y1 = u0;
}

double PidAxis::step(double q_m, double q_ref_m, bool& saturated) {
  const double e = q_m - q_ref_m;
  // Filtered backward difference: a first-order low-pass on de/dt.
  const double raw_deriv = (e - prev_error_m_) / dt_s_;
  deriv_m_s_ = deriv_alpha_ * deriv_m_s_ + (1.0 - deriv_alpha_) * raw_deriv;
  prev_error_m_ = e;

  const double p_term = p_.kp_n_per_m * e;
  const double d_term = p_.kd_n_s_per_m * deriv_m_s_;
  double u = -(p_term + integral_n_ + d_term);
  if (has_lead_) u = lead_.step(u);
  for (int i = 0; i < p_.notch_count; ++i) u = notch_[static_cast<size_t>(i)].step(u);

  saturated = std::abs(u) > force_limit_n_;
  const double u_sat = std::clamp(u, -force_limit_n_, force_limit_n_);
  // Conditional integration: do not integrate further into saturation.
  const double di = p_.ki_n_per_m_s * e * dt_s_;
  const bool pushes_further = saturated && ((u > 0.0 && di < 0.0) || (u < 0.0 && di > 0.0));
  if (!pushes_further)
    integral_n_ = std::clamp(integral_n_ + di, -p_.integrator_limit_n, p_.integrator_limit_n);
  return u_sat;
}

}  // namespace amb::fw
