#pragma once
// Reduced 4-DOF Hertzian bearing model of seed 003 (eq. 1-8, Algorithm 1): inner ring + shaft
// (m1, c1, k1 to ground) and outer ring + housing (m2, c2, k2 to ground) in the radial plane,
// coupled by the ball contacts of HertzContactLaw (radial clearance, groove defects),
// driven by a time-varying shaft speed N(t).
//
//   m1 x_i'' + c1 x_i' + k1 x_i = W_x - F_x      m2 x_o'' + c2 x_o' + k2 x_o = F_x
//   m1 y_i'' + c1 y_i' + k1 y_i = W_y - F_y      m2 y_o'' + c2 y_o' + k2 y_o = F_y   (eq. 7)
//
// State (9): [x_i, x_i', y_i, y_i', x_o, x_o', y_o, y_o', shaft angle]; the shaft angle is the
// integral of 2 pi N(t) so that the cage and an inner-race defect follow a varying speed.
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "model/bearing/hertz_contact.hpp"

namespace amb::model::bearing {

/// Parameters of the 4-DOF model. Defaults: seed 003 (6206, m1 5 kg, m2 10 kg, c1 1300 Ns/m,
/// c2 2200 Ns/m, k1 7.42e7 N/m, k2 1.51e7 N/m, 500 N radial load of its defect tests).
struct Hertz4DofParams {
  BearingGeometry bearing{"SKF 6206", 9, 9.525e-3, 46.0e-3, 0.0, "seed 003 section 3"};
  /// Nominal Hertz constant k_b,nom, N/m^1.5. 0 selects nominal_hertz_constant(bearing)
  /// (seed 003 gives no number for it).
  double hertz_constant_n_per_m1p5 = 0.0;
  /// Stiffness scale eta (seed 003 section 4.1): k_b = eta k_b,nom, dimensionless (> 0).
  double stiffness_scale = 1.0;
  /// Radial clearance delta_0, m. ASSUMED 5 um (seed 003 gives no value; 6206 normal
  /// clearance group is 5-20 um).
  double radial_clearance_m = 5e-6;
  double shaft_mass_kg = 5.0;               ///< m1, kg
  double shaft_damping_n_s_per_m = 1300.0;  ///< c1, N s/m
  double shaft_stiffness_n_per_m = 7.42e7;  ///< k1, N/m
  double housing_mass_kg = 10.0;            ///< m2, kg
  double housing_damping_n_s_per_m = 2200.0;  ///< c2, N s/m
  double housing_stiffness_n_per_m = 1.51e7;  ///< k2, N/m
  double load_x_n = 0.0;    ///< external load W_x on the inner ring, N
  double load_y_n = 500.0;  ///< external load W_y on the inner ring, N (+y: the load zone is at +90 deg)
  GrooveDefect defect;      ///< optional outer- or inner-race groove (eq. 4-5)
  BallSizeVariation ball_size;  ///< optional: one ball larger than the others (healthy imperfection)
  /// Direction of the housing accelerometer in the radial plane, rad from +x (default +y).
  double sensor_angle_rad = 1.5707963267948966;
  /// Largest integration step, s. 0: automatic (see choose_step_s).
  double max_step_s = 0.0;
  /// Time simulated before t = 0 at speed N(0) so start-up transients decay, s (>= 0).
  double settle_s = 0.1;
};

/// Integration state: [x_i, x_i', y_i, y_i', x_o, x_o', y_o, y_o', shaft angle] (m, m/s, rad).
using Hertz4DofState = Eigen::Matrix<double, 9, 1>;

/// The configured model (parameters + precomputed contact law). Immutable after configure().
class Hertz4DofModel {
 public:
  /// Validate and precompute; returns false if any parameter is out of range.
  bool configure(const Hertz4DofParams& p);
  /// Right-hand side of eq. 7 at shaft speed shaft_speed_hz (Hz). No allocation.
  Hertz4DofState derivative(const Hertz4DofState& y, double shaft_speed_hz) const noexcept;
  /// Support force (force on the outer ring) in state y.
  SupportForce support_force(const Hertz4DofState& y) const noexcept;
  /// Equivalent contact stiffness of eq. 8, N/m: |F| / |r_in - r_out| (0 if no relative motion).
  double equivalent_stiffness_n_per_m(const Hertz4DofState& y) const noexcept;
  /// A start state near the static equilibrium (rings displaced along the load).
  Hertz4DofState initial_state() const;
  /// Housing acceleration along the sensor direction, m/s^2, from a derivative vector.
  double sensor_acceleration(const Hertz4DofState& dydt) const noexcept;
  /// Integration step rule: the largest h <= max_shaft_speed-dependent bounds
  ///   h <= 0.05 * 2 pi / w_max  (w_max: fastest linearised mode, contact linearised at the
  ///                              Stribeck peak ball load 5 W / Z),
  ///   h <= defect transit time / 4 (a ball crossing the groove, or a ball's spot crossing a
  ///        race, at max speed; no bound when the applied depth is 0),
  ///   h <= max_step_s if set,
  /// then shrunk so that an integer number of steps fits one output period 1/fs_hz.
  double choose_step_s(double max_shaft_speed_hz, double fs_hz) const;

  const Hertz4DofParams& params() const { return p_; }
  const HertzContactLaw& contact() const { return law_; }

 private:
  Hertz4DofParams p_{};
  HertzContactLaw law_{};
  bool ok_ = false;
};

/// Simulate the housing (outer-race / pedestal) acceleration, m/s^2, along
/// p.sensor_angle_rad, sampled at fs_hz for duration_s.
/// @param p               model parameters (validated; throws std::invalid_argument if invalid)
/// @param shaft_speed_hz  shaft speed N(t)/60 as a function of time t_s in s (Hz); evaluated at
///                        max(t, 0) during the settling time before t = 0
/// @param fs_hz           output sample rate, Hz (> 0)
/// @param duration_s      length of the output record, s (> 0)
/// @param noise_rms       standard deviation of added white Gaussian noise, m/s^2 (>= 0)
/// @param noise_seed      seed of the noise generator (mt19937_64): same seed, same record
/// @return floor(duration_s * fs_hz) samples; sample k is at t = k / fs_hz
std::vector<double> simulate_housing_acceleration(const Hertz4DofParams& p,
                                                  const std::function<double(double t_s)>& shaft_speed_hz,
                                                  double fs_hz, double duration_s, double noise_rms,
                                                  uint64_t noise_seed);

/// Same, writing into `out` (resized once) so callers that repeat simulations (identification)
/// reuse memory. The model must be configured. Does not add noise.
void simulate_housing_acceleration_into(const Hertz4DofModel& model,
                                        const std::function<double(double t_s)>& shaft_speed_hz,
                                        double fs_hz, double duration_s, std::vector<double>& out);

}  // namespace amb::model::bearing
