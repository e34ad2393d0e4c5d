#pragma once
// First auxiliary-bearing contact model (to be replaced by a non-smooth Moreau-Jean contact
// behind the same Plant interface): a penalty normal force with damping that never pulls,
// and regularised Coulomb friction between the rotor collar and the bearing's inner ring.
// Real-time safe: no allocation, bounded iterations.
#include <cmath>

#include "model/plant/plant_params.hpp"

namespace amb::model {

/// What the contact needs to know about the rotor and the ring at one sub-step.
struct ContactState {
  double x_m = 0.0, y_m = 0.0;         ///< rotor centre at the bearing plane (sensor frame), m
  double vx_m_s = 0.0, vy_m_s = 0.0;   ///< its velocity, m/s
  double spin_rad_s = 0.0;             ///< rotor spin speed about +z, rad/s
  double ring_rad_s = 0.0;             ///< inner-ring speed about +z, rad/s
  double lateral_inv_mass_1_per_kg = 0.0; ///< 1 / effective rotor mass at the plane (modal), 1/kg
  double spin_inertia_kg_m2 = 0.0;     ///< rotor polar inertia, kg m^2
};

/// Forces on the rotor and torques, positive along +x, +y, +z.
struct ContactResult {
  double fx_n = 0.0, fy_n = 0.0;       ///< total contact force on the rotor, N
  double normal_n = 0.0;               ///< normal force magnitude (>= 0), N
  double friction_n = 0.0;             ///< tangential force on the rotor along t = z x n, N
  double spin_torque_n_m = 0.0;        ///< friction torque on the rotor, N m
  double ring_torque_n_m = 0.0;        ///< friction torque on the ring (drag excluded), N m
  double penetration_m = 0.0;          ///< max(0, |r - c| - clearance), m
  double slip_end_m_s = 0.0;           ///< slip velocity at the end of the sub-step (implicit), m/s
  double friction_power_w = 0.0;       ///< dissipated friction power (>= 0), W
};

/// Contact force over a sub-step of `h_s`. The friction force is found implicitly in the
/// slip velocity, F = -mu N phi(v_slip(t + h)), phi(v) = v / sqrt(v^2 + eps^2), so that a
/// stiff regularisation (small `slip_regularisation_m_s`) stays stable for light rings.
/// `hertz_exponent` 1 (default): linear penalty k d; 1.5: Hertz K d^1.5 with K such that the
/// contact stiffness dF/dd equals b.contact_stiffness_n_per_m at d = hertz_reference_m (the
/// board files' convention, 10 um).
ContactResult aux_contact(const AuxBearingParams& b, const ContactState& s, double h_s,
                          double slip_regularisation_m_s, double hertz_exponent = 1.0,
                          double hertz_reference_m = 10e-6);

/// Regularised sign: v / sqrt(v^2 + eps^2).
inline double regularised_sign(double v, double eps) { return v / std::sqrt(v * v + eps * eps); }

}  // namespace amb::model
