#pragma once
// Board files: the declarative description of a board, its rig, controller, capture and
// comms. Loaded and validated at configure time (never in the loop). A bad file is refused
// with a BoardError naming the key and the allowed range.
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>

#include "firmware/bearing/bearing_params.hpp"
#include "firmware/comms/comms_params.hpp"
#include "firmware/capture/capture_params.hpp"
#include "firmware/sweep/sweep_params.hpp"
#include "firmware/tracking/tracker_params.hpp"
#include "model/control/pid_params.hpp"
#include "model/journal/journal_rig.hpp"
#include "model/plant/plant_params.hpp"

namespace amb::board {

/// Operator-facing lifecycle settings.
struct LifecycleParams {
  double liftoff_ramp_s = 0.3;        ///< ramp of the position set-point from touchdown to centre, s
  double settle_s = 0.2;              ///< time the orbit must stay within settle_tolerance_m before "levitated", s
  double settle_tolerance_m = 0.0;    ///< orbit radius from the set-point counted as settled, m
  double operating_speed_hz = 0.0;    ///< speed the `run` command spins up to, Hz
  double spin_accel_hz_per_s = 10.0;  ///< speed ramp of the drive set-point, Hz/s
  double landing_ramp_s = 0.2;        ///< ramp of the set-point down to touchdown on landing, s
  double max_orbit_fault_m = 0.0;     ///< orbit radius at any sensor plane that latches a fault, m
  /// Consecutive loop periods without a fresh sample after which a levitated board enters the
  /// safe state (sensor_invalid). Key max_missed_samples, default 10.
  uint32_t max_missed_samples = 10;
};

struct BoardConfig {
  std::string source;                 ///< where it was loaded from ("embedded:NAME" or a path)
  std::string name;                   ///< board name
  std::string description;
  std::string backend;                ///< "sim", "linux" or "replay"
  model::PlantParams plant;           ///< the rig
  model::PidParams controller;        ///< per-axis position controller
  double rate_hz = 10000.0;           ///< control loop rate, Hz (1 kHz .. 40 kHz)
  /// [controller] loop_delay_periods: the loop's computation and transport delay, from the
  /// sample instant to the demand acting at the amplifiers, in loop periods (0 .. 2; default 0).
  /// The sim backend applies it (SimRig::set_demand_delay_ns), the closed-loop analysis rates
  /// the loop with it (ClosedLoopOptions::loop_delay_periods), amb-plant holds demands by it.
  double loop_delay_periods = 0.0;
  LifecycleParams lifecycle;
  fw::CaptureParams capture;          ///< [capture] and [triggers]; defaults when absent
  fw::TrackerParams tracker;          ///< on-board speed tracker ([tracker], optional)
  fw::BearingParams bearing;          ///< on-board bearing task ([bearing], optional)
  fw::SweepParams sweep;              ///< loop-sensitivity sweep ([sweep], optional; defaults per rate)
  comms::CommsParams comms;           ///< I/O wiring of the linux backend ([comms], optional)
  model::journal::JournalBearingParams journal;  ///< [journal_bearing] (optional; present = false without it)
  std::map<std::string, std::string> assumed;  ///< key path -> why the value is assumed
};

/// A refused board file. what() names the source, the key path and what was expected.
class BoardError : public std::runtime_error {
 public:
  BoardError(const std::string& source, const std::string& key, const std::string& message);
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

/// Parse and validate board-file text. `source` names it in errors.
BoardConfig parse_board(std::string_view toml_text, const std::string& source);

/// Load a board by embedded name ("bath-amb-rig") or by path to a .toml file.
BoardConfig load_board(const std::string& name_or_path);

/// Names of the boards compiled into this executable.
std::vector<std::string> embedded_board_names();

}  // namespace amb::board
