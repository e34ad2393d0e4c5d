#pragma once
// The board's analysis task (non-real-time), the same code behind every backend: the loop
// hands each fresh sample of the board's [tracker] channel to it through a lock-free SPSC
// ring (SampleSink::on_sample: no lock, no allocation, no wait; a full ring drops and counts);
// poll(), called by the analysis thread (AnalysisThread) or, in lock-step simulation, between
// loop periods, runs the STFT speed tracker on what arrived, publishes each update to the
// supervisor (Supervisor::publish_tracked_speed: one atomic store) and to readers of
// status(), and runs the bearing task's defect lines at the tracked speed.
// configure() allocates; on_sample() and poll() do not.
#include <atomic>
#include <cstdint>
#include <string>

#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/bearing/bearing_task.hpp"
#include "firmware/common/spsc_ring.hpp"
#include "firmware/tracking/speed_tracker_task.hpp"

namespace amb::board { struct BoardConfig; }
namespace amb::model { struct RotorParams; }

namespace amb::fw {

/// What the analysis task last computed (trivially copyable; read through a SeqLock).
struct AnalysisStatus {
  int64_t update_t_ns = 0;        ///< HAL time of the centre of the newest tracker window, ns
  double tracked_speed_hz = 0.0;  ///< newest tracker speed, Hz; NaN when lost or below the minimum
  double confidence = 0.0;        ///< its confidence, 0..1
  uint8_t lost = 1;               ///< 1: the newest update carries no speed (tracker lost, below its minimum, or confidence < min_confidence)
  uint8_t below_min = 0;          ///< 1: the track went below the tracker's stated minimum speed
  uint8_t mode = 0;               ///< model::signal::TrackMode
  uint8_t defects_valid = 0;      ///< 1: the defect lines below are at the newest tracked speed
  double ftf_hz = 0.0, bpfo_hz = 0.0, bpfi_hz = 0.0, bsf_hz = 0.0;  ///< monitored bearing's defect lines, Hz
  uint64_t tracker_updates = 0;   ///< tracker updates since configure
  uint64_t samples = 0;           ///< samples run through the tracker
  uint64_t gaps = 0;              ///< sequence gaps seen in the channel (missing or stale samples)
  uint64_t resets = 0;            ///< tracker restarts after a gap longer than max_gap_samples
  uint64_t ring_drops = 0;        ///< samples the loop could not hand over (ring full)
  uint64_t polls = 0;             ///< poll() calls
  uint8_t coasting = 0;           ///< 1: the newest update's window reaches past the drive's stop (no drive: the spin can only fall)
  uint64_t coast_rejections = 0;  ///< updates refused while coasting (window across the stop, or above the spin-down ceiling)
  double coast_ceiling_hz = 0.0;  ///< highest speed a coasting update may carry, Hz (0: no ceiling)
};

/// While the rotor coasts (drive set-point zero after it was running: the safe state after a
/// drop, a landing), nothing drives the spin, so it can only fall. A tracker update is then
/// published as lost ("not tracked", confidence 0) if its window straddles the stop (it mixes
/// the driven and the coasting spin), or if it lies above the last speed accepted before the
/// stop (or since, whichever is lower) by more than this fraction: that line is not the shaft
/// (after a drop the orbit's strongest line is the whirl). 0.05: the board's speed error bound.
inline constexpr double k_coast_rise_fraction = 0.05;

/// The rotor as one rigid body (the bearing task's quick-look momentum balance).
struct RigidRotorProperties {
  double mass_kg = 0.0;                   ///< total mass, kg
  double cm_axial_m = 0.0;                ///< centre of mass, m from the left end
  double transverse_inertia_kg_m2 = 0.0;  ///< about a diameter through the centre of mass, kg m^2
};
/// Mass properties of a board's rotor (beam elements and rigid disks). Configure time (allocates).
RigidRotorProperties rigid_rotor_properties(const model::RotorParams& rotor);

/// The bearing task's settings from a board's [bearing] table and rig (aux clearance and
/// planes, the rigid rotor's mass properties, gravity).
BearingTaskConfig bearing_task_config(const board::BoardConfig& board);

class AnalysisTask final : public SampleSink {
 public:
  /// Validate and allocate from the board's [tracker] and [bearing] tables. `sup` receives the
  /// tracked speed (may be null). Returns empty on success, else what is wrong. A board whose
  /// tracker is disabled gives an idle task (enabled() false): on_sample() does nothing.
  std::string configure(const board::BoardConfig& board, Supervisor* sup);
  bool enabled() const { return enabled_; }
  bool bearing_configured() const { return bearing_.configured(); }

  /// [RT, loop thread] Offer the tracker channel of one loop sample. Samples whose read
  /// failed are not offered (the tracker sees a gap, never a held value as a new sample).
  void on_sample(const LoopSample& s) override;
  /// [RT, loop thread] Switch the hand-off off or on (off: on_sample does nothing).
  void set_feeding(bool on) { feeding_.store(on, std::memory_order_relaxed); }

  /// [analysis thread] Drain the ring, track, publish. Returns samples consumed.
  size_t poll();

  /// [any thread] Newest results (lock-free).
  AnalysisStatus status() const { return published_.load(); }
  /// [any thread] Samples handed over by the loop and not yet analysed.
  size_t queued_samples() const { return tracker_.queued(); }
  /// [any thread] Samples dropped because the ring was full.
  uint64_t ring_drops() const { return tracker_.ring_drops(); }
  const SpeedTrackerTask& tracker_task() const { return tracker_; }

 private:
  bool enabled_ = false;
  int channel_ = 0;
  double min_confidence_ = 0.0;
  Supervisor* sup_ = nullptr;
  SpeedTrackerTask tracker_;
  BearingTask bearing_;
  SeqLock<AnalysisStatus> published_;
  AnalysisStatus st_{};
  uint64_t seen_updates_ = 0;
  std::atomic<bool> feeding_{true};
  // Coast detection: the loop thread stores the HAL time the drive set-point fell to zero
  // (-1: driven, or never driven); the analysis thread keeps the spin-down ceiling.
  bool drive_on_ = false;  // loop thread
  std::atomic<int64_t> coast_start_ns_{-1};
  int64_t half_window_ns_ = 0;
  double last_driven_speed_hz_ = 0.0;  // newest accepted speed before the stop, Hz (0: none)
};

}  // namespace amb::fw
