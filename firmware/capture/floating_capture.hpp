#pragma once
// The floating capture (Phase A): every loop sample goes into a pre-allocated ring; when a
// trigger asserts, the window [trigger - pre, trigger + post) is copied into one of a few
// pre-allocated event buffers and handed to a non-real-time consumer through an SPSC ring.
//
// Real-time side (on_sample, loop thread): bounded work per sample, no allocation, locks,
// system calls or exceptions. The copy of the pre-trigger history is spread over the
// post-trigger samples (ceil(pre/post) samples per period), so the loop never copies a whole
// window at once and never waits for the consumer. If no buffer is free at a trigger, the
// event is lost and counted (events_lost) — the loop does not wait.
//
// Re-arm policy: after a trigger the capture records the post-trigger window and freezes it;
// it re-arms only once the window is frozen (or the event was lost) AND every level
// condition has been clear continuously for capture.rearm_hold_s. One event per incident.
//
// Consumer side (one non-real-time thread): take() the next frozen event, read it, release() it.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "firmware/app/loop_runner.hpp"
#include "firmware/capture/capture_params.hpp"
#include "firmware/capture/frozen_event.hpp"
#include "firmware/capture/trigger_monitor.hpp"
#include "firmware/common/spsc_ring.hpp"

namespace amb::fw {

/// Counters since configure (any thread may read; written by the loop thread only).
struct CaptureCounters {
  uint64_t samples = 0;           ///< samples seen
  uint64_t triggers = 0;          ///< triggers accepted (capture started)
  uint64_t events_frozen = 0;     ///< windows frozen and handed off
  uint64_t events_lost = 0;       ///< triggers while no buffer was free
  uint64_t triggers_suppressed = 0;  ///< causes that asserted while capturing or not re-armed
  uint64_t seq_gaps = 0;          ///< discontinuities of LoopSample::seq seen by the capture
};

class FloatingCapture final : public SampleSink {
 public:
  enum class Mode : uint8_t { armed = 0, capturing = 1, holdoff = 2 };
  static constexpr int k_max_buffers = 8;

  FloatingCapture();
  ~FloatingCapture() override;

  /// Allocate the ring and the event buffers (not real-time). `sensor_angle_deg`: sensor
  /// directions [A1, A2, B1, B2], deg from the upward vertical; `rate_hz`: loop rate, Hz.
  /// Must not run concurrently with on_sample/take/release.
  void configure(const CaptureParams& p, const std::array<double, 4>& sensor_angle_deg, double rate_hz);

  /// [RT] One loop sample.
  void on_sample(const LoopSample& s) override;

  /// Any thread: request a manual trigger (taken at the next sample). False if the manual
  /// trigger is disabled in the board file.
  bool request_manual_trigger();

  /// [consumer] The oldest frozen event not yet taken, or nullptr. Valid until release().
  const FrozenEvent* take();
  /// [consumer] Give a taken event's buffer back to the loop.
  void release(const FrozenEvent* e);

  CaptureCounters counters() const;
  Mode mode() const { return static_cast<Mode>(mode_pub_.load(std::memory_order_relaxed)); }
  uint32_t pre_samples() const { return pre_n_; }
  uint32_t post_samples() const { return post_n_; }
  size_t ring_samples() const { return ring_.size(); }
  const TriggerMonitor& monitor() const { return monitor_; }

 private:
  void start(const LoopSample& s, uint32_t causes);
  void freeze();
  void bump(std::atomic<uint64_t>& c) { c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed); }

  // Configuration.
  CaptureParams p_{};
  uint32_t pre_n_ = 0, post_n_ = 1, pre_per_sample_ = 1, hold_n_ = 1;
  std::vector<LoopSample> ring_;
  uint64_t ring_mask_ = 0;
  std::vector<FrozenEvent> events_;
  std::unique_ptr<SpscRing<uint32_t, k_max_buffers>> ready_;  ///< loop -> consumer
  std::unique_ptr<SpscRing<uint32_t, k_max_buffers>> free_;   ///< consumer -> loop
  TriggerMonitor monitor_;

  // Loop-thread state.
  uint64_t head_ = 0;              ///< samples written to the ring
  bool have_last_seq_ = false;
  uint64_t last_seq_ = 0;
  Mode mode_ = Mode::armed;
  uint32_t clear_n_ = 0;           ///< consecutive all-clear samples
  uint32_t cur_ = 0;               ///< buffer being filled
  uint64_t pre_src_ = 0;           ///< absolute ring index of the first pre-trigger sample
  uint32_t pre_count_ = 0, pre_done_ = 0, post_done_ = 0;
  uint32_t window_gaps_ = 0;
  uint64_t captures_ = 0;

  std::atomic<bool> manual_request_{false};
  std::atomic<uint8_t> mode_pub_{0};
  std::atomic<uint64_t> n_samples_{0}, n_triggers_{0}, n_frozen_{0}, n_lost_{0}, n_suppressed_{0}, n_gaps_{0};
};

}  // namespace amb::fw

namespace amb::board { struct BoardConfig; }

namespace amb::fw {
/// Configure `c` from a board: its [capture]/[triggers], rig sensor angles and loop rate.
void configure_capture(FloatingCapture& c, const board::BoardConfig& b);
}  // namespace amb::fw
