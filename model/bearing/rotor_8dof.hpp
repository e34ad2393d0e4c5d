#pragma once
// 8-DOF rotor-bearing model of seed 001 (eq. 1-6): a shaft lumped at the two bearing centres
// O1, O4 (masses m1, m4) and two discs O2, O3 (m2, m3), x and y each, chained by shaft
// stiffnesses; the bearings at O1 and O4 use the SAME HertzContactLaw as the 4-DOF model
// (outer races fixed to ground: eq. 1 has no housing DOF).
//
//   m1 x1'' + cs1 x1' + k1 (x1 - x2)                 = F_ax
//   m2 x2'' + cd1 x2' + k2 (x2 - x1) + k2 (x2 - x3)  = 0
//   m3 x3'' + cd2 x3' + k3 (x3 - x2) + k3 (x3 - x4)  = 0
//   m4 x4'' + cs2 x4' + k4 (x4 - x3)                 = F_bx        (y likewise, with - m g)
// F_a, F_b are the bearing reactions on the rotor: minus the ball force on the outer ring.
// (Seed 001 eq. 2 gives the ball-force sum with a + sign on the right of eq. 1; with a
// restoring reaction the sign must be -, as here.)
//
// Seed 001 gives only the rig geometry (Table 5: shaft 460 mm x r 5 mm, discs r 38 mm x 18 mm,
// 6200 bearings); masses, stiffnesses and damping below are ASSUMED from that geometry (steel):
// shaft 0.28 kg -> 0.07 kg lumped at each bearing, discs 0.64 kg each, shaft segment stiffness
// chosen so the first bending mode lands near the seed's measured critical speed 3788 rpm (63 Hz).
#include <functional>

#include <Eigen/Core>

#include "model/bearing/hertz_contact.hpp"

namespace amb::model::bearing {

/// Parameters of the 8-DOF model (defaults ASSUMED, see above).
struct Rotor8DofParams {
  double m1_kg = 0.07, m2_kg = 0.64, m3_kg = 0.64, m4_kg = 0.07;  ///< lumped masses, kg
  double cs1_n_s_per_m = 20.0, cs2_n_s_per_m = 20.0;  ///< damping at the bearings, N s/m
  double cd1_n_s_per_m = 20.0, cd2_n_s_per_m = 20.0;  ///< damping at the discs, N s/m
  double k1_n_per_m = 2.0e5, k2_n_per_m = 2.0e5, k3_n_per_m = 2.0e5, k4_n_per_m = 2.0e5;  ///< shaft, N/m
  double gravity_m_per_s2 = 9.81;  ///< g, m/s^2 (acts along -y)
  ContactLawParams bearing_a;      ///< bearing at O1 (geometry, k_b, clearance, defect)
  ContactLawParams bearing_b;      ///< bearing at O4
  /// Fixed RK4 step, s (contact mode of the light lumped masses is ~20 kHz). With a defect it
  /// must also resolve the defect's transit: step_s <= HertzContactLaw::defect_transit_time_s(
  /// max shaft speed) / 4 (a 0.3 mm ball spot on a 6200 at 40 Hz: ~0.3 ms, far above 2 us).
  double step_s = 2e-6;
};

/// State: positions [x1 y1 x2 y2 x3 y3 x4 y4] (m), velocities (m/s), shaft angle (rad).
using Rotor8DofState = Eigen::Matrix<double, 17, 1>;

/// Configured model. Never allocates after configure().
class Rotor8DofModel {
 public:
  /// Validate and build both contact laws; false if out of range.
  bool configure(const Rotor8DofParams& p);
  /// Time derivative at shaft speed shaft_speed_hz, Hz.
  Rotor8DofState derivative(const Rotor8DofState& y, double shaft_speed_hz) const noexcept;
  /// Advance by one fixed step (RK4); returns the derivative at the step start.
  Rotor8DofState step(Rotor8DofState& y, double t_s, const std::function<double(double)>& shaft_speed_hz) const;
  /// Reaction of bearing A (index 0) or B (1) on the rotor in state y, N.
  SupportForce bearing_reaction(const Rotor8DofState& y, int bearing) const noexcept;
  const Rotor8DofParams& params() const { return p_; }

 private:
  Rotor8DofParams p_{};
  HertzContactLaw law_a_{}, law_b_{};
};

}  // namespace amb::model::bearing
