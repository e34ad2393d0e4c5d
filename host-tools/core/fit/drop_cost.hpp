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
// Both the measurement and the simulation pass through the same sensor view (sensor_orbit.hpp).
#include <array>
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
};

/// What the cost compares, for one event window (samples after the trigger).
struct DropFeatures {
  double period_s = 0.0;
  std::array<model::drop::RubbingDurations, 2> rubbing{};  ///< per aux bearing
  std::vector<std::array<double, 4>> plane_xy_m;           ///< (xA, yA, xB, yB) at the sensor planes, m
  std::vector<double> speed_rad_s;                         ///< empty when not measured
};

/// Features of a window of sensor readings [A1, A2, B1, B2] (m) sampled at `period_s`;
/// the aux-bearing centres and clearances come from `rig` (offsets as given there).
DropFeatures drop_features(const model::PlantParams& rig, const model::drop::SensorOrbit& view,
                           const std::vector<std::array<double, 4>>& sensor_m, const std::vector<double>& speed_rad_s,
                           double period_s, double spin_sign, const model::drop::RubbingOptions& rubbing);

struct CostBreakdown {
  double rubbing = 0.0, orbit = 0.0, speed = 0.0, total = 0.0;
};

/// Cost of `sim` against `meas` (same window length; the shorter one sets it).
CostBreakdown drop_cost(const DropFeatures& meas, const DropFeatures& sim, double clearance_m, double speed0_rad_s,
                        const DropCostWeights& w);

}  // namespace amb::host::fit
