#pragma once
// The supervisor: lifecycle (unconfigured -> inactive -> levitating -> running -> fault) and
// the fixed-step control step read -> step -> write. Parameters are fixed at configure;
// step() is real-time: no allocation, locks, system calls, exceptions or logging.
#include <array>
#include <atomic>
#include <cstdint>
#include <string>

#include "firmware/app/loop_sample.hpp"
#include "firmware/board/board.hpp"
#include "firmware/common/spsc_ring.hpp"
#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"
#include "firmware/sweep/sweep_generator.hpp"
#include "model/amb/amb_force.hpp"
#include "hal/types.hpp"

namespace amb::fw {

enum class State : uint8_t { unconfigured = 0, inactive = 1, levitating = 2, running = 3, fault = 4 };
const char* to_string(State s);

/// Operator commands; posted from any thread, taken by the loop at the next step.
enum class Command : uint8_t { none = 0, levitate, run, land, reset_fault, emergency_stop };
const char* to_string(Command c);

/// Why the safe state was entered.
enum class FaultReason : uint8_t {
  none = 0,
  orbit_limit,        ///< orbit radius beyond lifecycle.max_orbit_fault_m at a sensor plane
  amplifier_fault,    ///< amplifier fault input asserted
  sensor_invalid,     ///< analog front end reported no/invalid samples for too long
  emergency_stop,     ///< operator
  comm_timeout,       ///< field-bus node heartbeat lost
  overrun,            ///< too many consecutive loop overruns
};
const char* to_string(FaultReason r);

/// Sub-phase within levitating/running, for operators and tests.
enum class Phase : uint8_t { idle = 0, lifting, settling, levitated, spinning_up, at_speed,
                             spinning_down, lowering };
const char* to_string(Phase p);

/// Fault counters (never reset except at configure() and reset()).
struct FaultCounters {
  uint64_t read_failures = 0;
  uint64_t sensor_fault_samples = 0;
  uint64_t saturated_steps = 0;
  uint64_t rejected_commands = 0;
  uint64_t safe_state_entries = 0;
  uint64_t speed_disagreements = 0;  ///< tracker updates off the tachometer by more than tracker.tach_disagreement_fraction
  uint64_t speed_lost_periods = 0;   ///< periods whose speed estimate was lost (speed source tracker, or a NaN tach)
};

/// The tracked speed as the loop sees it (Status::tracked).
struct TrackedSpeedView {
  double speed_hz = 0.0;      ///< newest tracker speed, Hz; NaN when lost, stale or none yet
  double confidence = 0.0;    ///< its confidence, 0..1 (0 when stale)
  bool lost = true;           ///< no valid tracked speed (tracker lost, below its minimum, stale or absent)
  bool stale = false;         ///< the tracker has not updated for more than tracker.stale_after_s
  double age_s = 0.0;         ///< loop time since the tracker's last update, s
  uint64_t updates = 0;       ///< tracker updates the loop has seen
};

/// The loop's part of the status, published every step (one SeqLock store of these words).
struct LoopStatus {
  int64_t t_ns = 0;
  uint64_t step = 0;
  State state = State::unconfigured;
  Phase phase = Phase::idle;
  FaultReason fault = FaultReason::none;
  std::array<double, 4> xy_m{};           ///< [xA, yA, xB, yB] at the sensor planes, m
  std::array<double, 2> orbit_radius_m{}; ///< radius from the set-point per plane, m
  std::array<double, 4> current_demand_a{};
  double speed_command_hz = 0.0;
  double speed_estimate_hz = 0.0;         ///< per tracker.speed_source (see LoopSample); NaN when lost
  double speed_confidence = 0.0;          ///< confidence of speed_estimate_hz, 0..1
  bool speed_lost = false;                ///< speed_estimate_hz is not a valid speed
  double tach_speed_hz = -1.0;            ///< tachometer reading, Hz (<0: none)
  TrackedSpeedView tracked;               ///< the tracker's speed as the loop sees it
  FaultCounters counters;
};

/// Snapshot for other threads (supervisory link, CLI, tests): the loop's part, published every
/// step, and the sweep's, which the generator publishes only when it changes (a start, a period
/// or an axis done, the end) so that an idle generator adds nothing to the step's publication
/// (docs/sweep.md "Cost in the loop"). Both are as of the latest step; the two are read one after
/// the other, so the sweep part may be one step newer than the loop part.
struct Status : LoopStatus {
  SweepStatus sweep;                      ///< loop-sensitivity sweep: progress, aborts, refusals
};

class Supervisor {
 public:
  /// Allocates nothing after this. Throws std::invalid_argument on inconsistent config.
  void configure(const board::BoardConfig& board);
  /// Back to the state configure() leaves (inactive, PID states, counters, set-points, the
  /// pending command and the tracker updates cleared), the board's parameters kept; what
  /// configure() does after loading them. Configure time, not [RT]; needs configure() first.
  void reset();
  /// Any thread: post a command. Returns false if a command is still pending.
  bool post(Command c);
  /// One thread (the analysis thread): publish a tracker update: speed (Hz; ignored when
  /// `lost`), confidence (0..1), lost flag. Lock-free (one 64-bit atomic store); the loop
  /// takes it at its next step and ages it: an update older than tracker.stale_after_s is
  /// treated as lost.
  void publish_tracked_speed(double speed_hz, double confidence, bool lost);
  /// Compatibility: publish a speed with full confidence (<0 or NaN: lost).
  void set_tracked_speed_hz(double hz) { publish_tracked_speed(hz, 1.0, !(hz >= 0.0)); }

  /// [RT] One loop period. `in_ok` false: the front end had no valid sample.
  void step(const hal::AnalogInputs& in, bool in_ok, const hal::DiscreteInputs& din,
            hal::AnalogOutputs& out, hal::DiscreteOutputs& dout);
  /// [RT] The one path to the safe state: amplifiers and drive off, reason latched.
  void enter_safe_state(FaultReason reason);

  /// The record of the last step (for the capture ring).
  const LoopSample& last_sample() const { return sample_; }
  /// Latest status (lock-free snapshot; any thread).
  Status status() const {
    Status s;
    static_cast<LoopStatus&>(s) = published_.load();
    s.sweep = sweep_.published_status();
    return s;
  }
  State state() const { return state_; }
  double period_s() const { return dt_s_; }

  /// The loop-sensitivity sweep (docs/sweep.md "Board side"). Any thread: request a start or
  /// an abort (taken at the next step; a start the loop refuses is counted with its reason).
  void request_sweep_start() { sweep_.request_start(); }
  void request_sweep_abort() { sweep_.request_abort(); }
  /// Any thread: why a start would be refused now, from the latest status and the
  /// configuration (none: the loop will start it unless the state changes meanwhile).
  SweepRefusal sweep_start_refusal() const;
  /// The generator: its design, configuration and, for the event thread, the finished record.
  SweepGenerator& sweep() { return sweep_; }
  const SweepGenerator& sweep() const { return sweep_; }
  /// The sweep's configuration error ("" when it can run), from configure().
  const std::string& sweep_config_error() const { return sweep_error_; }

 private:
  void handle_command(Command c);
  /// [RT] The sweep's part of a step, called only while the generator is not quiet: the
  /// excitation added at the summing point of its axis (out.current_demand_a, after the
  /// controller's limit), the record, the sweep status published when it changed. Kept out of
  /// line so that the step's control path is the same code with the generator idle.
  void step_sweep(int64_t t_ns, hal::AnalogOutputs& out);
  void set_phase(Phase p) { phase_ = p; phase_t_s_ = 0.0; }

  board::BoardConfig board_{};
  double dt_s_ = 1e-4;
  std::array<PidAxis, 4> pid_{};           ///< [xA, yA, xB, yB]
  std::array<AxisTransform, 2> xf_{};      ///< per bearing plane
  std::array<double, 2> ki_n_per_a_{};
  std::array<model::magnet::AxisLaw, 2> law_{};                 ///< board's AMB force law, per plane
  std::array<std::array<std::array<double, 2>, 2>, 2> act_dir_{}; ///< actuator axis unit vectors (x, y)
  std::array<double, 2> weight_share_n_{}; ///< static load of each bearing plane, N (lever rule)

  State state_ = State::unconfigured;
  Phase phase_ = Phase::idle;
  FaultReason fault_ = FaultReason::none;
  double phase_t_s_ = 0.0;
  std::array<double, 4> ref_m_{};          ///< set-point per control axis, m
  std::array<double, 4> touchdown_m_{};    ///< position at the levitate command, m
  double speed_cmd_hz_ = 0.0;
  uint32_t consecutive_read_failures_ = 0;
  uint64_t step_count_ = 0;
  uint64_t seq_ = 0;
  bool watchdog_ = false;
  FaultCounters counters_{};
  LoopSample sample_{};
  LoopStatus status_{};
  SeqLock<LoopStatus> published_;
  std::atomic<uint8_t> pending_{0};
  // Tracked speed: f32 speed bits | confidence percent << 32 | lost << 40 | update counter << 48.
  std::atomic<uint64_t> tracked_packed_{0};
  uint16_t tracked_publish_count_ = 0;    ///< writer side (analysis thread)
  uint16_t tracked_seen_update_ = 0;      ///< loop side
  uint64_t tracked_updates_seen_ = 0;
  uint64_t tracked_age_steps_ = 0;
  bool driven_ = false;                   ///< the drive set-point was > 0 last period
  bool tracked_predates_stop_ = false;    ///< the newest tracked update was made before the drive stopped
  uint64_t stale_steps_ = 0;
  SweepGenerator sweep_;
  std::string sweep_error_;
};

}  // namespace amb::fw
