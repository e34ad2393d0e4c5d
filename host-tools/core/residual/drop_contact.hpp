#pragma once
// Contact geometry of a drop event, the model-light evidence of the drop part's candidates.
// While the rotor touches an aux bearing (rolling, whirling, or at the bottom of a bounce),
// its centre at that bearing's plane lies on a circle about the bearing's centre (radius =
// clearance + contact deflection). Two effects break that in a way no drop-model parameter
// can:
//  * Sensor runout (a speed-locked artefact of the sensor target) stays in the readings after
//    the amplifiers are cut: the measured contact points then leave the circle by a vector
//    that turns with the rotor angle. Unbalance is a real force: in contact it only modulates
//    the contact deflection (|F_u| times the contact compliance, well below a micrometre on
//    the rigs here), so the spin-locked radial residual of the contact points tells runout
//    from unbalance at one speed -- which the levitated part cannot: there the controller
//    acts on the measured displacement, so the current is the known controller's response to
//    (x_true + r) and a two-plane unbalance reproduces any forward 1x runout exactly.
//  * Compliance under an aux bearing (a pedestal) adds a deflection proportional to the
//    contact force at that bearing only: the contact radius grows with the contact force
//    beyond what the contact law gives (force from the rotor's rigid-body dynamics; the
//    amplifiers are off, so gravity, contacts and unbalance are the only forces).
// Pure functions of the readings, the spin angle and the board; no drop-model fit.
#include <array>
#include <complex>
#include <string>
#include <vector>

#include "model/rig/rig_model.hpp"
#include "model/effects/effect_set.hpp"
#include "model/plant/plant_params.hpp"

namespace amb::host::residual {

struct ContactGeometryOptions {
  double contact_band = 0.9;     ///< candidate contact samples: radius about the board's centre >= this x clearance
  double trim_sigma = 3.0;       ///< contact samples kept: |radial residual of the circle fit| <= this x its robust scale
  double decorrelation_s = 1e-3; ///< samples closer than this count as one (standard errors, BIC), at least; s
                                 ///< (longer when the residual's own correlation time is: integrated autocorrelation)
  double min_points = 40.0;      ///< decorrelated contact points needed per bearing
};

/// Rotor angle over the drop readings: theta (rad) per sample and whether it is known (a
/// speed record after the trigger; the levitated part's refined speed before it).
struct SpinAngle {
  std::vector<double> theta_rad;
  std::vector<char> known;
};

/// Spin-locked vectors at the two sensor planes (orders 1 and 2, as model::effects::SensorRunout)
/// estimated from the contact points together with both contact circles.
struct ContactRunout {
  bool testable = false;
  std::string why_not;                                        ///< when not testable
  model::effects::SensorRunout runout;                        ///< phasors in the angle reference of `SpinAngle`, m
  std::array<std::array<double, model::effects::k_runout_orders>, 2> sigma_m{};  ///< standard error of each phasor component, m
  std::array<std::array<double, 2>, 2> centre_m{};            ///< circle centres with the runout removed, m
  std::array<double, 2> radius_m{};                           ///< effective contact radii, m
  std::array<int, 2> points{};                                ///< contact samples used per bearing
  double n_eff = 0.0;                                         ///< decorrelated contact points (both bearings)
  double ssr_without_m2 = 0.0, ssr_with_m2 = 0.0;             ///< circles only / circles + runout, same points, m^2
  double delta_bic = 0.0;                                     ///< n_eff ln(ssr_without/ssr_with) - 8 ln n_eff
  double spin_min_hz = 0.0, spin_max_hz = 0.0;                ///< spin range over the points used, Hz
  /// Largest |phasor| / standard error over planes and orders.
  double largest_z() const;
};

/// Which phasors [plane][order-1] are free in the fit (the others are held at zero).
using RunoutMask = std::array<std::array<bool, model::effects::k_runout_orders>, 2>;
inline constexpr RunoutMask k_all_runout_phasors{{{true, true}, {true, true}}};

/// Readings [A1, A2, B1, B2] (m) after the trigger with their rotor angle (same length).
/// delta_bic counts 2 parameters per free phasor.
ContactRunout estimate_contact_runout(const std::vector<std::array<double, 4>>& sensor_m, const SpinAngle& angle,
                                      const model::PlantParams& rig, double fs_hz, const ContactGeometryOptions& o = {},
                                      const RunoutMask& free = k_all_runout_phasors);

/// What the base model's own unbalance makes look like runout in contact, per sensor plane
/// (order 1), m: with the rotor held at both aux-bearing contacts, the unbalance forces
/// `force_n` at `axial_m` (rotating at `spin_hz`) bend the shaft between the contacts (FE
/// rotor, pinned at the aux planes, harmonic at the spin frequency without gyroscopics) and
/// the sensors see that bending as a spin-locked vector; the modulation of the contact
/// deflection (|F| times the contact compliance at the weight share) is added. Magnitudes
/// summed (an upper bound over the phases).
/// `rig_model`: the board's rig model (model/rig), whose rotor and planes are `rig`'s.
std::array<double, 2> unbalance_contact_signature_m(const model::PlantParams& rig, const model::RigModel& rig_model,
                                                     const std::array<double, 2>& force_n,
                                                     const std::array<double, 2>& axial_m, double spin_hz);

/// How the straight-line sensor view misplaces the aux-bearing centres of a flexible rotor
/// resting on both aux bearings (y, m, per aux plane): under gravity the shaft bends between
/// the two contacts (FE rotor pinned at the aux planes), the sensors see the sagged shaft and
/// their straight line through the two sensor planes passes the aux planes off the contact
/// points by this much. Zero for a rotor without bending flexibility; the bias a rigid drop
/// model does not reproduce.
struct SagViewShift {
  std::array<double, 2> shift_m{};  ///< per aux plane, along y (negative: the view sits low), m
  double weight_n = 0.0;            ///< the rotor's weight that makes it, N
};
SagViewShift gravity_sag_view_shift_m(const model::PlantParams& rig, const model::RigModel& rig_model);

/// Readings with the runout removed (each sensor's projection of the plane's vector), where
/// the angle is known; elsewhere unchanged.
std::vector<std::array<double, 4>> remove_runout(const std::vector<std::array<double, 4>>& sensor_m, const SpinAngle& angle,
                                                 const model::effects::SensorRunout& r, const model::PlantParams& rig);

/// Probe sensitivity from the contact geometry: a probe whose gain is off by a factor reads the
/// clearance circle as an ellipse stretched along its own axis. The contact points (all
/// samples after the trigger whose radius about the board's centre is >= contact_band x
/// clearance, trimmed as for the runout) are fitted with both circles and, per sensor plane,
/// the log gain ratio a_p = ln(g_p1 / g_p2) of its two probes (the readings divided by
/// g = e^{+-a/2} before the straight-line view to the aux planes). A common gain of a plane's
/// two probes only scales the circles and is not identified here (the effective radius is a
/// nuisance); the ratio is.
struct ContactGain {
  bool testable = false;
  std::string why_not;
  std::array<double, 2> log_ratio{};        ///< a_p = ln(g_p1 / g_p2) per sensor plane, 1
  std::array<double, 2> sigma{};            ///< its standard error, 1
  std::array<int, 2> points{};              ///< contact samples per bearing
  double n_eff = 0.0;                       ///< decorrelated contact points (both bearings)
  double ssr_without_m2 = 0.0, ssr_with_m2 = 0.0;  ///< circles only / circles + gain ratios, m^2
  double delta_bic = 0.0;                   ///< n_eff ln(ssr_without / ssr_with) - (free ratios) ln n_eff
};

/// `free[p]`: fit plane p's ratio (else held at 0).
ContactGain estimate_contact_gain(const std::vector<std::array<double, 4>>& sensor_m, const model::PlantParams& rig,
                                  double fs_hz, const ContactGeometryOptions& o = {},
                                  const std::array<bool, 2>& free = {true, true});

/// Readings with the probe gains divided out (g_p1 = e^{a_p/2}, g_p2 = e^{-a_p/2}).
std::vector<std::array<double, 4>> remove_gain_ratio(const std::vector<std::array<double, 4>>& sensor_m,
                                                     const std::array<double, 2>& log_ratio);

/// Force-deflection of the contacts per aux bearing from the readings: the contact force
/// from the rigid rotor's dynamics (amplifiers off: m a = contact forces + weight; the
/// unbalance force is below the resolution and left out) and the radial deflection of the
/// contact point beyond the clearance circle; regressed as deflection = d0 + law(F) + F / k_s
/// with the board's contact law `law(F)` held, so 1 / k_s is the compliance the contact law
/// does not explain (a support under the bearing).
struct ContactCompliance {
  bool testable = false;
  std::string why_not;
  std::array<double, 2> compliance_m_per_n{};   ///< 1 / k_s per bearing (may be < 0 within the noise), m/N
  std::array<double, 2> sigma_m_per_n{};        ///< its standard error, m/N
  std::array<double, 2> mean_force_n{};         ///< mean contact force over the points used, N
  std::array<double, 2> force_span_n{};         ///< 10 %..90 % range of the contact force, N
  std::array<double, 2> deflection_change_m{};  ///< predicted change of the contact radius over that force span, m
  std::array<double, 2> noise_m{};              ///< scatter of the deflection about the regression, m
  std::array<int, 2> points{};
  std::array<double, 2> delta_bic{};            ///< per bearing: the 1 / k_s term against none
};

ContactCompliance estimate_contact_compliance(const std::vector<std::array<double, 4>>& sensor_m,
                                              const model::PlantParams& rig, const model::RigModel& rig_model, double fs_hz,
                                              const std::array<std::array<double, 2>, 2>& centre_m,
                                              const ContactGeometryOptions& o = {});

}  // namespace amb::host::residual
