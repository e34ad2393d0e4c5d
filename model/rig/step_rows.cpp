#include "model/rig/step_rows.hpp"

#include <stdexcept>

namespace amb::model {
StepModeVec to_step_vec(const Eigen::RowVectorXd& r) {
  StepModeVec v(r.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) v(i) = r(i);
  return v;
}

StepRows make_step_rows(const RigModel& rig, const RigReduction& red, const PlantParams& p, const std::string& who) {
  StepRows s;
  s.modes = red.modes();
  if (s.modes > k_step_max_modes)
    throw std::invalid_argument(who + ": modes per plane (" + std::to_string(s.modes) + ") exceed the capacity of " +
                                std::to_string(k_step_max_modes));
  s.spin_inertia_kg_m2 = rig.rotor().polar_inertia_kg_m2;
  if (!(s.spin_inertia_kg_m2 > 0.0)) throw std::invalid_argument(who + ": rotor has no polar inertia");

  s.w2 = to_step_vec(red.reduced.omega2.transpose());
  s.damp = to_step_vec(red.reduced.damping.transpose());
  s.polar = red.reduced.polar;
  // Gravity along -y on the consistent mass: f = Phi^T M (-g t), t = unit translation.
  s.gravity_y = to_step_vec(red.gravity_y_n.transpose());
  for (size_t b = 0; b < 2; ++b) {
    s.amb[b] = to_step_vec(red.amb[b]);
    s.aux[b] = to_step_vec(red.aux[b]);
    s.law[b] = magnet::make_axis_law(p.amb[b]);
    for (size_t a = 0; a < 2; ++a) s.act_dir[2 * b + a] = magnet::axis_direction(p.amb[b].actuator_angle_deg[a]);
  }
  for (size_t k = 0; k < 4; ++k) {
    s.sensor[k] = to_step_vec(red.sensor[k]);
    s.sensor_dir[k] = magnet::axis_direction(p.sensor[k].angle_deg);
  }
  s.coupling = to_step_vec(red.coupling);

  // Unbalance: disk d at angle a_d = phase_d - theta from the vertical. Its force
  // u (W^2 (sin a, cos a) + W' (cos a, -sin a)) expands in cos(theta), sin(theta) with the
  // two sums S = sum b_d u_d sin(phase_d), C = sum b_d u_d cos(phase_d). The unbalance is
  // p's own, the disk rows the rig model's.
  const UnbalanceExpansion unb = unbalance_expansion(red, p.rotor);
  s.unb_sin = to_step_vec(unb.sin_sum.transpose());
  s.unb_cos = to_step_vec(unb.cos_sum.transpose());
  s.mid_disk = to_step_vec(unb.mid_row);
  s.mid_disk_phase_rad = unb.mid_phase_rad;
  return s;
}

}  // namespace amb::model
