#pragma once
// The rigid-body part of a flexible rotor's measured orbit during a drop.
//
// After the amplifiers are cut the only lateral loads on the rotor are gravity and the two
// aux-bearing contacts, at known axial planes. Two sensor planes cannot tell the rigid-body
// motion from the bending of the free-free rotor, but with the loads confined to the aux
// planes the bending is a known function of the record: in one lateral plane, with the
// mass-normalised free-free modes split into the two rigid-body ones (r) and the lowest
// bending ones (f),
//   q_r'' = A_r^T F + g_r,   q_f'' + D_f q_f' + W_f q_f = A_f^T F + g_f,   y = S_r q_r + S_f q_f
// (A: mode shapes at the aux planes, S: at the sensor planes, g: modal gravity, D, W: modal
// damping and stiffness). Eliminating F and q_r leaves
//   L q_f'' + D_f q_f' + W_f q_f = E y'' + c,   L = I + P S_r^-1 S_f,  E = P S_r^-1,
//   P = A_f^T A_r^-T,  c = g_f - P g_r,
// which this class integrates with u = L q_f - E y as state, so the measured displacements
// y drive it without being differentiated twice (y' enters only through the small modal
// damping). The rigid-body part of the sensor readings is then y - S_f q_f: put through the
// rigid-body momentum balance it gives the contact forces of the flexible rotor.
// The system is the inverse of the rotor's path from the aux-plane forces to the sensors; it
// is usable when its own modes (eigenvalues of L^-1 W_f) are oscillatory and damped, i.e.
// when the sensor planes are close enough to the aux planes (`usable()`).
// Gyroscopic coupling of the bending modes is neglected (their frequencies are well above
// the spin speed of a drop); loads at other planes (unbalance, the bias flux of the magnets
// right after the cut) are not in it.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::drop {

class FlexibleOrbit {
 public:
  /// `rotor` built from `params`; `sensor_axial_m` the two sensor planes, `aux_axial_m` the two
  /// aux-bearing planes (m from the rotor's left end); `bending_modes` >= 1 lowest free-free
  /// bending modes per lateral plane taken into account; `gravity_m_s2` along -y.
  /// Throws std::invalid_argument when the planes coincide or the rotor has no bending mode.
  FlexibleOrbit(const rotor::RotorModel& rotor, const RotorParams& params, std::array<double, 2> sensor_axial_m,
                std::array<double, 2> aux_axial_m, int bending_modes, double gravity_m_s2);
  /// The same from a rig model's modal basis (no new eigen solve); gravity is the rig's.
  FlexibleOrbit(const RigModel& rig, std::array<double, 2> sensor_axial_m, std::array<double, 2> aux_axial_m,
                int bending_modes);

  /// True when every mode of the inverse system is stable (eigenvalues of L^-1 W_f real and
  /// positive): the correction can be integrated over a record.
  bool usable() const { return usable_; }
  /// Frequencies of the inverse system's modes, Hz (0 for a non-positive eigenvalue).
  const std::vector<double>& inverse_frequencies_hz() const { return inverse_hz_; }
  /// Frequencies of the bending modes used, Hz.
  const std::vector<double>& bending_frequencies_hz() const { return bending_hz_; }

  /// Per sample (x0, y0, x1, y1): the rotor centre at sensor planes 0 and 1, m, sampled at
  /// `dt_s`; returns the rigid-body part of the same readings. At the first sample the rotor
  /// is taken straight and at rest (the sag between the magnets before the cut, < 1 um at
  /// the sensors of the Bath rig, is neglected).
  /// `with_gravity` false: the path of a signal alone (e.g. probe noise), without the weight.
  std::vector<std::array<double, 4>> rigid_part(const std::vector<std::array<double, 4>>& planes_m, double dt_s,
                                                bool with_gravity = true) const;
  /// The same integration, returning the rotor centre at the two aux-bearing planes per
  /// sample (x0, y0, x1, y1), m: the rigid-body part extrapolated to the aux planes plus the
  /// bending there. This is where the rotor touches its aux bearings; the straight line
  /// through the two sensor planes misses it by the bending between the planes.
  std::vector<std::array<double, 4>> aux_planes(const std::vector<std::array<double, 4>>& planes_m, double dt_s) const;

 private:
  /// Integrates the bending coordinates q_f over the record and calls
  /// `sample(i, plane, q_f)` at every sample (plane 0: x, 1: y).
  template <class PerSample>
  void integrate(const std::vector<std::array<double, 4>>& planes_m, double dt_s, bool with_gravity,
                 PerSample&& sample) const;
  void init(const rotor::RotorModel& rotor, const rotor::ReducedRotor& red, std::array<double, 2> sensor_axial_m,
            std::array<double, 2> aux_axial_m, double gravity_m_s2);
  int nf_ = 0;
  Eigen::MatrixXd s_f_;           // 2 x nf: bending shapes at the sensor planes
  Eigen::MatrixXd a_f_;           // 2 x nf: bending shapes at the aux planes
  Eigen::Matrix2d s_r_inv_;       // rigid-body shapes at the sensor planes, inverted
  Eigen::Matrix2d a_r_;           // rigid-body shapes at the aux planes
  Eigen::MatrixXd l_inv_, e_;     // nf x nf, nf x 2
  Eigen::VectorXd d_f_, w_f_;     // modal damping (1/s) and stiffness (rad/s)^2
  Eigen::VectorXd c_y_;           // constant modal load from gravity in the y plane
  bool usable_ = false;
  std::vector<double> inverse_hz_, bending_hz_;
};

}  // namespace amb::model::drop
