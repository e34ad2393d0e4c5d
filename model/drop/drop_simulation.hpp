#pragma once
// A drop scenario run on the drop model, recorded per sample for Phase D (seed 000 2.4:
// contact forces, rotor orbit, auxiliary-bearing ring motion and rotor speed vs time):
// levitate at speed under the internal PID, then at the trigger apply the known faults and
// switch the amplifiers off (seed 000 section 6: "both AMBs are switched off"), and record.
#include <array>
#include <vector>

#include "model/drop/drop_model.hpp"

namespace amb::model::drop {

struct DropScenario {
  double speed_hz = 45.0;          ///< drive speed before the drop, Hz (seed 000: 2700 rpm)
  double settle_s = 0.1;           ///< levitated time before the trigger (not recorded), s
  double pre_trigger_s = 0.01;     ///< levitated history kept in the record before the trigger, s
  double window_s = 0.4;           ///< recorded time after the trigger, s
  double sample_rate_hz = 10000.0; ///< record rate (also the plant step() length), Hz
  bool amplifiers_off = true;      ///< at the trigger the amplifiers are disabled (all channels cut)
  PlantFaults faults;              ///< fault parameters applied at the trigger (times relative to it)
};

/// One record sample (values at the sample's end; forces are means over the sample).
struct DropSample {
  double t_s = 0.0;                           ///< time from the trigger, s
  double spin_rad_s = 0.0;                    ///< rotor speed, rad/s
  std::array<double, 4> sensor_m{};           ///< displacement sensors [A1, A2, B1, B2] (noise incl.), m
  std::array<double, 2> aux_x_m{}, aux_y_m{}; ///< rotor centre at each aux-bearing plane (truth), m
  std::array<double, 2> normal_n{};           ///< mean normal contact force, N
  std::array<double, 2> friction_n{};         ///< mean friction force on the rotor along z x n, N
  std::array<double, 2> contact_fraction{};   ///< share of the sample's steps with the contact closed
  std::array<double, 2> ring_rad_s{};         ///< inner-ring speed, rad/s
  std::array<double, 2> ring_angle_rad{};     ///< inner-ring angle (mod 2 pi), rad
};

struct DropTrace {
  int trigger_index = 0;                      ///< first sample after the trigger
  double sample_period_s = 0.0;               ///< record period, s
  std::vector<DropSample> samples;
  std::vector<StepContact> contact_steps;     ///< every Moreau-Jean step with a closed contact (Phase E input)
  EnergyLedger ledger;                        ///< at the end of the window
  DropCounters counters;                      ///< of the recorded part
};

/// Reset to the levitated centre at `speed_hz` and run `settle_s` with the amplifiers on
/// (internal controller) to reach the pre-drop state. The model must use the internal controller.
void levitate(DropModel& model, const DropScenario& sc);

/// From the model's current (levitated) state: record `pre_trigger_s`, trigger, record
/// `window_s`. `keep_contact_steps`: also keep every contact step (for the load map).
DropTrace record_drop(DropModel& model, const DropScenario& sc, bool keep_contact_steps);

/// levitate() then record_drop().
DropTrace simulate_drop(DropModel& model, const DropScenario& sc, bool keep_contact_steps = true);

}  // namespace amb::model::drop
