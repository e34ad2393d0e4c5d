#pragma once
// Friction coefficient of the aux bearings read directly from a measured drop (issue 13):
// the contact forces from the rotor's rigid-body momentum balance, and the ratio of their
// tangential to their normal part while the collar slides on the inner ring.
//
// Why: once the rotor bounces chaotically or whirls backward, the pointwise orbit depends on
// the friction through the whole history, and a model fitted to it can trade the friction
// against the contact law (a fit on backward-whirl drops came out 20-50 % high). The forces
// do not: after the amplifiers are cut, the only forces on the rotor are gravity and the two
// aux-bearing contacts, so
//   m a_G = F_A + F_B - m g e_y,   It b'' + Omega Ip G b' = (z_A - z_G) F_A + (z_B - z_G) F_B
// (x and y planes, b the slopes; rotor_model.hpp's sign convention) gives F_A and F_B from the
// measured orbit's second derivative. Split into the normal part N (along the contact radius,
// towards the bearing centre) and the tangential part T, Coulomb's law says |T| <= mu N with
// equality while sliding; during a drop the collar (surface speed Omega r, metres per second)
// slides on each impact and in a forward rub until the ring has spun up; in a rolling
// backward whirl it does not (T << mu N there). So the estimate is the upper cluster of the
// windowed impulse ratios sum(T) / sum(N): the windows in which the collar slid. With a speed
// channel sum(T) comes from the spin-down (friction_from_speed).
//
// Signals: the four displacement sensors (two planes) give the rigid-body position and slope;
// second derivatives by a quadratic least-squares fit over +-smoothing_half_window_s (nulls a
// flexible rotor's bending ringing near 1 kHz at +-1 ms). The speed channel, when present,
// gives the spin-down over the sliding windows, compared with the one the estimated friction
// torque r sum(T) implies (Ip dOmega/dt = -r sum T, both bearings).
// Reads the measurement and the rig's geometry and inertia only; no model simulation.
#include <array>
#include <string>
#include <vector>

#include "host-tools/core/fit/drop_measurement.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"

namespace amb::host::fit {

struct FrictionEstimateOptions {
  /// Half width of the derivative fit, s (halved for the smoothing check): about a Hertz
  /// impact's duration (0.2-0.5 ms here); longer ones smear an impact over a changing contact
  /// angle, shorter ones pass the flexible rotor's ringing.
  double smoothing_half_window_s = 0.5e-3;
  /// Fewer sliding windows than this: no estimate (valid false; the fit then fits the friction).
  int min_sliding_windows = 3;
  double skip_s = 5e-3;                   ///< left out after the trigger (coil currents decaying), s
  double max_window_s = 0.5;              ///< end of the analysed record after the trigger, s
  double window_s = 0.005;                ///< length of one ratio window, s
  /// When fewer than min_sliding_windows windows of window_s slide (the rotor locks into a
  /// rolling whirl within a few ms at high speed and friction), the windows are halved, down
  /// to this length, s (0: no retry). About two derivative half-widths: shorter windows hold
  /// one impact's smeared force.
  double min_window_s = 0.00125;
  /// A sample counts as in contact at a bearing when the aux-plane orbit radius is at least
  /// this fraction of the clearance (the derivative fit smears an impact over its half width,
  /// while the rotor moves away from the ring), 1.
  double contact_radius_fraction = 0.8;
  /// Windows whose normal impulse is below this fraction of the largest window's are not used
  /// (a grazing touch: ratio of two small numbers), 1.
  double min_impulse_fraction = 0.02;
  /// A window counts as sliding when its ratio lies within [f, 1/f] x the estimate (the band
  /// holding the largest friction impulse, re-centred on its weighted ratio), 1.
  double sliding_fraction = 0.75;
  /// One window per bearing (true) or one for both bearings together (false: the sums over
  /// both contacts; the split of the force between the bearings rests on the moment balance,
  /// i.e. on the transverse inertia and the sensor-plane slope, and scatters more).
  bool per_bearing = false;
  /// With a speed channel (and per_bearing false): the friction impulse of a window from the
  /// spin-down, Ip (Omega_start - Omega_end) / r, instead of the tangential contact forces.
  /// The normal force is the large, robust part of the force estimate (an error in the
  /// contact angle changes it to second order); the tangential part is small next to it and
  /// an angle error of a few mrad moves it by per cent of N (backward whirl: N of kN). The
  /// speed channel measures the friction torque on the rotor directly (nothing else acts on
  /// its spin after the cut: no drive, no AMB).
  bool friction_from_speed = true;
  /// The speed drop of a window taken as the sum of dOmega/dt from the same +-half-width
  /// quadratic fit that gives the contact forces (true), or as the raw speed difference
  /// across the window (false). The forces are smeared over +-smoothing_half_window_s, so an
  /// impact near a window edge puts part of its normal impulse into the next window while
  /// the raw speed drop stays in this one; through the same fit both spread alike. On the
  /// independent simulator's drops (../shared/data/synthetic) this moved the estimates
  /// from +1.1 % / +0.9 % to -0.1 % / -0.1 % and cut the window scatter by 3 x.
  bool matched_speed_filter = true;
  /// Leave out a sliding window whose neighbour in time is a rolling window (ratio below the
  /// sliding band) with a larger normal impulse, when at least min_sliding_windows others
  /// remain: at the lock-in into a rolling whirl the derivative fit smears the rolling
  /// contact's normal impulse, which carries no friction, across the window edge.
  bool drop_next_to_rolling = true;
  /// A sliding window is "clear" when no neighbour in time rolls (ratio below the sliding
  /// band) with a normal impulse above this fraction of its own (0: not checked). With fewer
  /// than min_sliding_windows clear windows the windows are halved (down to min_window_s)
  /// as long as the halved ones still give min_sliding_windows sliding windows: next to the
  /// lock-in into a rolling whirl a window has often slid only part of its length (the ring
  /// caught up), and shorter windows confine that to one of them.
  double clear_neighbour_fraction = 0.1;
  /// Remove the synchronous (1x) force and moment from the momentum balance: a rotor's
  /// unbalance accelerates its geometric centre (what the sensors see) by e Omega^2 without any
  /// contact force; left in, it adds a rotating force of m e Omega^2 to every window (with an
  /// unbalance of 1e-4 kg m per disk at 45 Hz, 21 N against 60 N of a bouncing window's mean
  /// normal force). Fitted as F = Omega^2 U e^{i theta}, M = Omega^2 V e^{i theta} (complex
  /// x + i y, theta the spin angle integrated from the speed channel) by least squares over
  /// the samples near contact, where the friction torque the tangential forces imply must equal
  /// the speed channel's, and the free-flight samples, where the whole force is the unbalance's.
  /// Needs a speed channel and a record of at least synchronous_min_revolutions revolutions.
  bool remove_synchronous = true;
  double synchronous_min_revolutions = 2.0;  ///< 1
  /// Lowest free-free bending modes of the board's FE rotor whose deflection is taken out of
  /// the sensor readings before the rigid-body momentum balance (model/drop/flexible_orbit.hpp:
  /// the loads act at the aux planes only, so the bending follows from the record); 0: the
  /// rotor is taken as rigid between the sensor planes. With bending_modes > 0 both
  /// descriptions are estimated and one is chosen (FrictionEstimate::bending_modes,
  /// rotor_choice): by the force each leaves in free flight beyond the probe noise when either
  /// leaves one (a description that misreads the rotor leaves a ringing force where the true
  /// force is zero), else by the smaller uncertainty (the windows that agree better).
  int bending_modes = 1;
  /// Free-flight samples (per bearing: that bearing not within the derivative fit's reach of
  /// contact) needed before the free-flight force counts as evidence.
  int min_free_flight_samples = 20;
  std::string check() const;  ///< empty when usable
};

/// One ratio window at one bearing.
struct FrictionWindow {
  int bearing = 0;                 ///< 0: A, 1: B, -1: both (FrictionEstimateOptions::per_bearing false)
  double start_s = 0.0;            ///< after the trigger, s
  double length_s = 0.0;           ///< window length, s
  double normal_impulse_n_s = 0.0; ///< sum of N dt over the contact samples, N s
  double friction_impulse_n_s = 0.0; ///< sum of T dt (opposing the collar's surface speed: > 0), N s
  double ratio = 0.0;              ///< friction / normal impulse, 1
  double force_friction_impulse_n_s = 0.0; ///< from the tangential forces when the friction impulse is from the speed, N s
  bool sliding = false;            ///< in the upper cluster the estimate uses
  /// Left out: in the sliding band but next to a heavier rolling window
  /// (FrictionEstimateOptions::drop_next_to_rolling).
  bool next_to_rolling = false;
};

struct FrictionEstimate {
  bool valid = false;              ///< false: no sliding contact found (note says why)
  double friction = 0.0;           ///< impulse-weighted ratio over the sliding windows, 1
  /// Standard error of that weighted mean over the windows, combined with the change of the
  /// estimate when the derivative fit's half width is halved (smoothing bias), 1.
  double uncertainty = 0.0;
  double standard_error = 0.0;     ///< the first part, 1
  double smoothing_change = 0.0;   ///< the second part (signed: half-width estimate - this), 1
  int windows_used = 0, windows_total = 0;
  double window_s = 0.0;           ///< window length the estimate used (window_s, or shorter: min_window_s), s
  double sliding_time_s = 0.0;     ///< total length of the time windows with a sliding bearing, s
  /// Spin-down over those time windows: measured from the speed channel (sum of speed drops,
  /// through the derivative fit when matched_speed_filter, / sliding time) and implied by the estimated contact forces (r sum T / Ip, both bearings,
  /// same windows); rad/s^2, 0 when the speed is not measured.
  double measured_spin_down_rad_s2 = 0.0;
  double force_spin_down_rad_s2 = 0.0;
  /// Standard error of the difference of the two spin-downs from its window-to-window
  /// scatter (the tangential force of one window is small next to N and scatters with the
  /// contact angle's error), rad/s^2; 0 with fewer than two windows or no speed channel.
  double force_spin_down_scatter_rad_s2 = 0.0;
  /// The synchronous force removed (remove_synchronous): fitted or not, on how many samples,
  /// its force and moment amplitudes at the trigger speed, N and N m.
  bool synchronous_removed = false;
  int synchronous_fit_samples = 0;
  double synchronous_force_n = 0.0;
  double synchronous_moment_n_m = 0.0;
  /// Rotor description the forces come from: 0 rigid between the sensor planes, else the
  /// bending modes taken out (FrictionEstimateOptions::bending_modes); rotor_choice says what
  /// chose it: "free_flight" (the force left where no contact acts), "uncertainty" (no such
  /// evidence: the smaller uncertainty), empty (only the rigid one was estimated).
  int bending_modes = 0;
  std::string rotor_choice;
  /// One bearing's force in free flight (that bearing not near contact, averaged over
  /// +-0.25 ms), rms, for the rigid and the bent description (0 when not computed), N, over
  /// free_flight_samples (sample, bearing) pairs; and the board's probe noise put through the
  /// same description and filters, N.
  std::array<double, 2> free_flight_force_rms_n{};
  std::array<double, 2> free_flight_noise_rms_n{};
  int free_flight_samples = 0;
  std::vector<FrictionWindow> windows;
  std::string note;
};

/// Estimate from `m` (amplifiers cut at the trigger) on the rig `rig`. Throws
/// std::invalid_argument for unusable options or a record too short to analyse.
FrictionEstimate estimate_friction(const DropMeasurement& m, const model::PlantParams& rig,
                                   const FrictionEstimateOptions& o = {});
/// The same on the rig model built once by the caller (its rotor and planes must be `rig`'s).
FrictionEstimate estimate_friction(const DropMeasurement& m, const model::PlantParams& rig, const model::RigModel& rig_model,
                                   const FrictionEstimateOptions& o = {});

}  // namespace amb::host::fit
