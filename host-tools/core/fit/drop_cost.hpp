#pragma once
// The Phase C cost (seed 000 eq. 1-2) plus the terms that make it usable by an optimiser.
//  * Rubbing term (eq. 1): sum over both aux bearings of
//      c_swing |dt_swing| + c_fwrub |dt_fwrub| + c_bwrub |dt_bwrub|   (s)
//    with c_swing << c_fwrub << c_bwrub (eq. 2; defaults 1 : 3 : 10 per s), dt = simulated
//    minus measured duration of each rubbing state (model/drop/rubbing_states.hpp).
//    Durations change in steps of one sample, so this term alone is piecewise constant.
//  * Orbit term: RMS over the first orbit_window_s after the trigger of the distance between
//    simulated and measured rotor centres at both sensor planes, divided by the aux-bearing
//    clearance (1). It is graded where the durations are flat and compares where the rotor
//    went, not only in which state; sensor planes because that is what is measured. Only the
//    first impacts: bouncing is chaotic, so later orbits diverge for any parameter error (or
//    a micrometre difference in the pre-drop state) and would only add noise.
//  * Speed term (when speed is measured): RMS of the speed difference over the window,
//    divided by 1 % of the speed at the trigger. The spin-down is set by the friction
//    torque mu N R, the most direct trace of the friction coefficient in the data.
//  * Features that stay meaningful once the motion is chaotic (issue 13), per aux bearing:
//    spin-down rate (least-squares slope of the speed over the window, / 1 % of the trigger
//    speed per s), share of the window in contact, mean whirl rate of the contact angle while
//    in contact (signed, / the spin speed) and bounce rate (contact onsets per s, / 100 per s).
//    They compare statistics of the motion, not where the rotor is at a given instant.
//  * Backward whirl (the measurement's dominant state at an aux bearing is a backward rub):
//    when the rotor locks into rolling whirl is a chaotic event, and the whirl frequency, the
//    pointwise speed and the spin-down over the whole window all follow from it
//    (docs/drop-model.md, "Backward whirl lock-in"). Then the speed, spin-down and whirl terms
//    compare features of the sustained whirl AFTER each record's own lock-in instead
//    (LockInFeatures): the speed level (the LS line of the speed after lock-in at the window
//    end; set by the angular momentum through the lock-in), the drag-limited spin-down after
//    lock-in (LS slope) and, per bearing, the force-penetration relation of the whirl
//    (centripetal acceleration r psi'^2 against the penetration d = r - c: K / m_eff =
//    r psi'^2 / d^e with the contact law's exponent e), compared as |ln| of the ratio.
//    Bouncing records keep the terms above unchanged.
// Both the measurement and the simulation pass through the same sensor view (sensor_orbit.hpp).
#include <array>
#include <string>
#include <vector>

#include "model/drop/rubbing_states.hpp"
#include "model/drop/sensor_orbit.hpp"
#include "model/plant/plant_params.hpp"

namespace amb::host::fit {

struct DropCostWeights {
  double swing_per_s = 1.0;     ///< c_swing, 1/s
  double forward_per_s = 3.0;   ///< c_fwrub, 1/s
  double backward_per_s = 10.0; ///< c_bwrub, 1/s
  double orbit = 1.0;           ///< weight of the orbit term, 1
  double orbit_window_s = 0.015; ///< the orbit term covers the first this-many seconds after the trigger, s
  double speed = 3.0;           ///< weight of the speed term, 1
  double spin_down = 3.0;       ///< weight of the spin-down-rate term (per 1 % of the trigger speed per s), 1
  double contact_share = 1.0;   ///< weight of the contact-share difference (0..1), 1
  double whirl = 1.0;           ///< weight of the whirl-rate difference (/ spin speed), 1
  double bounce = 0.2;          ///< weight of the bounce-rate difference (/ 100 per s), 1
  /// Backward-whirl records: compare the sustained whirl after lock-in (LockInFeatures) in
  /// place of the pointwise speed, the whole-window spin-down and the mean whirl rate. Off by
  /// default (`amb-host fit --lock-in-cost`): it identifies the ring drag and example 2's
  /// contact stiffness, but moves the residual loop's aux-offset estimate on the generated
  /// offset record beyond its test bound (docs/drop-model.md).
  bool lock_in_features = false;
  double lock_in_speed = 3.0;   ///< weight of the speed level after lock-in (/ 1 % of the trigger speed), 1
  double lock_in_spin_down = 3.0; ///< weight of the spin-down after lock-in (/ 1 % of the trigger speed per s), 1
  double whirl_force = 3.0;     ///< weight of |ln| of the force-penetration ratio, per bearing, 1
  /// Weight of the mean whirl-rate difference (/ spin speed, as `whirl`) kept for backward-whirl
  /// records: the whirl frequency itself follows the lock-in, so well below `whirl`, 1
  double lock_in_whirl_rate = 0.0;
  double lock_in_margin_s = 0.04; ///< the sustained whirl starts this long after the backward state's onset, s
  double lock_in_min_s = 0.05;  ///< shortest sustained whirl compared, s
};

/// The sustained backward whirl of one record (from the orbit and the speed only).
struct LockInFeatures {
  bool valid = false;            ///< a backward whirl lasting at least lock_in_min_s after lock-in
  double start_s = -1.0;         ///< start of the compared part (latest bearing's onset + margin), s
  double speed_level_rad_s = 0.0;///< LS line of the speed after start_s, at the window end, rad/s
  double spin_down_rad_s2 = 0.0; ///< -(its slope), rad/s^2
  /// Per bearing: mean centripetal acceleration r psi'^2 (m/s^2) and mean penetration r - c
  /// (m) over the contact samples after start_s, r about the whirl's own centre (least-squares
  /// circle through those samples) (0: no sustained backward whirl there).
  std::array<double, 2> centripetal_m_s2{}, penetration_m{};
  std::array<bool, 2> whirling{};///< this bearing whirls backward in the compared part
  bool own = false;              ///< start_s from this record's own lock-in (else the override)
};

/// Whirl of one aux bearing over a window (from the orbit only; rubbing_states.hpp).
struct WhirlSummary {
  /// "none" (no contact), "bouncing" (swinging dominates), "forward" or "backward" (the
  /// rub state that lasts longest, when it lasts at least as long as the swinging).
  std::string direction = "none";
  double frequency_hz = 0.0;     ///< mean |whirl rate| over that state's samples, Hz (0: none)
  double onset_s = -1.0;         ///< first sample of that state after the window start, s (-1: none)
  double contact_share = 0.0;    ///< share of the window in contact, 1
  double whirl_rate_rad_s = 0.0; ///< mean signed contact-angle rate while in contact (+: with the spin), rad/s
  double bounce_rate_per_s = 0.0;///< contact onsets per second, 1/s
};

/// What the cost compares, for one event window (samples after the trigger).
struct DropFeatures {
  double period_s = 0.0;
  std::array<model::drop::RubbingDurations, 2> rubbing{};  ///< per aux bearing
  std::vector<std::array<double, 4>> plane_xy_m;           ///< (xA, yA, xB, yB) at the sensor planes, m
  std::vector<double> speed_rad_s;                         ///< empty when not measured
  std::array<WhirlSummary, 2> whirl{};                     ///< per aux bearing
  double spin_down_rad_s2 = 0.0;                           ///< -(LS slope of the speed), rad/s^2 (0: not measured)
  LockInFeatures lock_in;                                  ///< sustained backward whirl (valid = false: none)
  double contact_exponent = 1.0;                           ///< the simulated contact law's exponent (force relation), 1
};

/// The sustained backward whirl of a window: from the latest bearing's longest backward run.
/// `x`, `y` per bearing relative to its centre (m); speed may be empty.
LockInFeatures lock_in_features(const std::array<model::drop::RubbingResult, 2>& r, const std::array<std::vector<double>, 2>& x,
                                const std::array<std::vector<double>, 2>& y, const std::array<double, 2>& clearance_m,
                                const std::vector<double>& speed_rad_s, double period_s, double margin_s, double min_s,
                                double start_override_s = -1.0);

/// Whirl summary of one bearing's rubbing classification (`spin_sign` +1 or -1).
WhirlSummary whirl_summary(const model::drop::RubbingResult& r, double period_s, double spin_sign);

/// Features of a window of sensor readings [A1, A2, B1, B2] (m) sampled at `period_s`;
/// the aux-bearing centres and clearances come from `rig` (offsets as given there).
DropFeatures drop_features(const model::PlantParams& rig, const model::drop::SensorOrbit& view,
                           const std::vector<std::array<double, 4>>& sensor_m, const std::vector<double>& speed_rad_s,
                           double period_s, double spin_sign, const model::drop::RubbingOptions& rubbing,
                           double lock_in_margin_s = 0.04, double lock_in_min_s = 0.05, double lock_in_start_override_s = -1.0);

struct CostBreakdown {
  double rubbing = 0.0, orbit = 0.0, speed = 0.0, spin_down = 0.0, contact = 0.0, whirl = 0.0, bounce = 0.0, total = 0.0;
  bool lock_in = false;  ///< speed, spin_down and whirl compare the sustained backward whirl (LockInFeatures)
};

/// Cost of `sim` against `meas` (same window length; the shorter one sets it).
CostBreakdown drop_cost(const DropFeatures& meas, const DropFeatures& sim, double clearance_m, double speed0_rad_s,
                        const DropCostWeights& w);

}  // namespace amb::host::fit
