#include "model/bearing/rotor_8dof.hpp"

#include <cmath>

#include "model/bearing/rk4.hpp"

namespace amb::model::bearing {

bool Rotor8DofModel::configure(const Rotor8DofParams& p) {
  const double ms[] = {p.m1_kg, p.m2_kg, p.m3_kg, p.m4_kg};
  for (double m : ms)
    if (!(m > 0)) return false;
  if (p.k1_n_per_m < 0 || p.k2_n_per_m < 0 || p.k3_n_per_m < 0 || p.k4_n_per_m < 0 || !(p.step_s > 0)) return false;
  if (!law_a_.configure(p.bearing_a) || !law_b_.configure(p.bearing_b)) return false;
  p_ = p;
  return true;
}

SupportForce Rotor8DofModel::bearing_reaction(const Rotor8DofState& y, int bearing) const noexcept {
  const int i = bearing == 0 ? 0 : 6;  // x1 or x4 index
  SupportForce f = (bearing == 0 ? law_a_ : law_b_).force(y[i], y[i + 1], y[16]);
  f.fx_n = -f.fx_n;
  f.fy_n = -f.fy_n;
  return f;
}

Rotor8DofState Rotor8DofModel::derivative(const Rotor8DofState& y, double shaft_speed_hz) const noexcept {
  Rotor8DofState d;
  d.segment<8>(0) = y.segment<8>(8);
  const SupportForce fa = bearing_reaction(y, 0);
  const SupportForce fb = bearing_reaction(y, 1);
  const double g = p_.gravity_m_per_s2;
  for (int axis = 0; axis < 2; ++axis) {  // 0: x, 1: y
    const double q1 = y[0 + axis], q2 = y[2 + axis], q3 = y[4 + axis], q4 = y[6 + axis];
    const double v1 = y[8 + axis], v2 = y[10 + axis], v3 = y[12 + axis], v4 = y[14 + axis];
    const double fa_ax = axis == 0 ? fa.fx_n : fa.fy_n;
    const double fb_ax = axis == 0 ? fb.fx_n : fb.fy_n;
    const double grav = axis == 1 ? g : 0.0;
    d[8 + axis] = (fa_ax - p_.cs1_n_s_per_m * v1 - p_.k1_n_per_m * (q1 - q2)) / p_.m1_kg - grav;
    d[10 + axis] = (-p_.cd1_n_s_per_m * v2 - p_.k2_n_per_m * (q2 - q1) - p_.k2_n_per_m * (q2 - q3)) / p_.m2_kg - grav;
    d[12 + axis] = (-p_.cd2_n_s_per_m * v3 - p_.k3_n_per_m * (q3 - q2) - p_.k3_n_per_m * (q3 - q4)) / p_.m3_kg - grav;
    d[14 + axis] = (fb_ax - p_.cs2_n_s_per_m * v4 - p_.k4_n_per_m * (q4 - q3)) / p_.m4_kg - grav;
  }
  d[16] = 2.0 * M_PI * shaft_speed_hz;
  return d;
}

Rotor8DofState Rotor8DofModel::step(Rotor8DofState& y, double t_s,
                                    const std::function<double(double)>& shaft_speed_hz) const {
  auto rhs = [&](double t, const Rotor8DofState& s) { return derivative(s, shaft_speed_hz(t)); };
  return rk4_step<17>(rhs, t_s, y, p_.step_s);
}

}  // namespace amb::model::bearing
