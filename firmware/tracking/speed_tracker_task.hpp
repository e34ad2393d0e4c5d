#pragma once
// On-board speed tracking task (non-real-time). The loop thread offers one sample per
// period into a lock-free SPSC ring (fw::SpscRing, firmware/common); a slow thread calls
// poll(), which drains the ring into the STFT speed-ridge tracker; each update is published
// through a sequence lock (fw::SeqLock) that the loop and the supervisory link read without
// locks. configure() allocates; offer() and poll() never allocate, lock or throw.
#include <cstddef>
#include <cstdint>
#include <string>

#include "firmware/common/spsc_ring.hpp"
#include "model/signal/speed_ridge_tracker.hpp"

namespace amb::fw {

/// One input sample for the tracker (ring record).
struct TrackerSample {
  uint64_t seq = 0;    ///< loop period counter; a gap means lost samples
  int64_t t_ns = 0;    ///< HAL clock time of the sample, ns
  double value = 0.0;  ///< channel value (housing acceleration, g or m/s^2; or the 1x displacement, m)
};

/// The published estimate (trivially copyable, read through a SeqLock).
struct TrackedSpeed {
  int64_t t_ns = 0;            ///< HAL time of the centre of the analysed window, ns
  double speed_hz = 0.0;       ///< shaft speed, Hz; NaN when lost or below the minimum
  double confidence = 0.0;     ///< ridge confidence in [0, 1] (see SpeedEstimate)
  uint64_t update_seq = 0;     ///< increments with every update (0: none yet)
  uint8_t lost = 1;            ///< 1: no valid speed
  uint8_t below_min = 0;       ///< 1: below the tracker's stated minimum speed
  uint8_t mode = 0;            ///< model::signal::TrackMode
  uint8_t reserved = 0;
};

/// Ring capacity, samples: 2^15 = 3.3 s at 10 kHz, so poll() may run a few times a second.
inline constexpr size_t k_tracker_ring_capacity = size_t{1} << 15;

/// Counters of the task (read by the owning thread; approximate from others).
struct SpeedTrackerTaskCounters {
  uint64_t samples = 0;        ///< samples fed to the tracker
  uint64_t updates = 0;        ///< estimates published
  uint64_t gaps = 0;           ///< sequence gaps seen (lost samples in the loop or ring)
  uint64_t gap_samples = 0;    ///< samples bridged by holding the last value
  uint64_t resets = 0;         ///< tracker resets after a gap longer than max_gap_samples
  uint64_t ring_drops = 0;     ///< samples the loop could not offer (ring full)
};

/// The tracker task: owns the ring, the tracker and the published estimate.
class SpeedTrackerTask {
 public:
  /// Validate and allocate. `max_gap_samples`: gaps up to this many samples are bridged by
  /// repeating the last value; longer gaps reset the tracker (its window would be wrong).
  /// Returns empty on success, else the validation message (field name and range).
  std::string configure(const model::signal::SpeedTrackerOptions& options,
                        size_t max_gap_samples = 8);

  /// [RT, producer = loop thread] Offer one sample; false (counted) if the ring is full.
  bool offer(const TrackerSample& s) { return ring_.push(s); }

  /// [tracker thread] Drain up to `max_samples` samples and run the tracker; returns the
  /// number of samples consumed. Bounded by max_samples hops' worth of work; no allocation.
  size_t poll(size_t max_samples = k_tracker_ring_capacity);

  /// [any thread] Newest published estimate (lock-free).
  TrackedSpeed latest() const { return published_.load(); }

  const SpeedTrackerTaskCounters& counters() const { return counters_; }
  /// [any thread] Samples offered and not yet taken by poll() (approximate from other threads).
  size_t queued() const { return ring_.size(); }
  /// [any thread] Samples the producer could not offer because the ring was full.
  uint64_t ring_drops() const { return ring_.dropped(); }
  const model::signal::SpeedRidgeTracker& tracker() const { return tracker_; }

 private:
  void feed(double value);

  SpscRing<TrackerSample, k_tracker_ring_capacity> ring_;
  SeqLock<TrackedSpeed> published_;
  model::signal::SpeedRidgeTracker tracker_;
  SpeedTrackerTaskCounters counters_{};
  size_t max_gap_samples_ = 8;
  bool have_last_ = false;
  uint64_t last_seq_ = 0;
  int64_t first_t_ns_ = 0;
  double sample_period_ns_ = 0.0;
  double last_value_ = 0.0;
  uint64_t update_seq_ = 0;
};

}  // namespace amb::fw
