#pragma once
// The loop-sensitivity sweep generator (ISO 14839-3), board side: a multisine injected at the
// controller output of one control axis at a time (the current demand summing point:
// u = u_c + e, so S = u / e), with the responses recorded at the loop rate into a buffer
// allocated at configure time. Axes are swept one after the other: settle periods, then P
// recorded periods each.
//
// Threads: the loop checks quiet() every period and, unless quiet, calls begin_step(),
// end_step() and publish_status() ([RT]: a table lookup, a few comparisons and four stores, a
// status publication when it changed; no allocation, lock, system call or exception). Any thread may
// request a start or an abort (atomic flags, taken at the loop's next period) and count a
// refusal it made itself (the supervisory link). When a sweep ends (complete or aborted) the
// buffer is handed to the event thread (ready()); the loop does not touch it again until that
// thread calls release(). A start while the buffer is held is refused (busy).
#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "firmware/common/spsc_ring.hpp"
#include "firmware/sweep/multisine.hpp"
#include "firmware/sweep/sweep_params.hpp"

namespace amb::fw {

enum class SweepState : uint8_t { idle = 0, settling = 1, recording = 2, storing = 3 };
const char* to_string(SweepState s);

/// Why a sweep stopped before its last axis.
enum class SweepAbort : uint8_t { none = 0, orbit_limit = 1, operator_abort = 2, left_levitation = 3, fault = 4 };
const char* to_string(SweepAbort a);

/// Why a start was refused.
enum class SweepRefusal : uint8_t {
  none = 0,
  not_levitated = 1,    ///< not in the levitated or at-speed phase
  fault = 2,            ///< the supervisor is in the safe state
  not_armed = 3,        ///< supervisory link: the start was not armed
  amplitude_limit = 4,  ///< the configured amplitude exceeds the board's limit
  not_configured = 5,   ///< [sweep] disabled or its plan invalid
  busy = 6,             ///< a sweep is running or its record is still being stored
};
const char* to_string(SweepRefusal r);
inline constexpr int k_sweep_refusal_kinds = 7;

/// Progress and counters, published with the loop's status.
struct SweepStatus {
  SweepState state = SweepState::idle;
  int8_t axis = -1;                 ///< control axis being excited (0..3), -1 none
  uint8_t axis_index = 0;           ///< position of that axis in the sweep's order (0-based)
  uint8_t axes_total = 0;           ///< axes the sweep covers
  uint8_t axes_done = 0;            ///< axes completely recorded in the present (or last) sweep
  uint32_t period = 0;              ///< period of the present axis, 0-based (settle periods first)
  uint32_t periods_per_axis = 0;    ///< settle + recorded periods
  uint32_t started = 0;             ///< sweeps started since configure
  uint32_t completed = 0;           ///< sweeps that recorded every axis
  uint32_t aborts = 0;              ///< sweeps aborted
  uint32_t refusals = 0;            ///< starts refused (every reason)
  SweepAbort last_abort = SweepAbort::none;
  SweepRefusal last_refusal = SweepRefusal::none;
};

/// What the loop needs to decide this period.
struct SweepInputs {
  bool levitated = false;         ///< levitated or at-speed phase
  bool fault = false;             ///< safe state
  double orbit_max_m = 0.0;       ///< largest orbit radius from the set-point over the sensor planes, m
  int64_t t_ns = 0;               ///< HAL time of this period's sample, ns
  uint64_t seq = 0;               ///< loop period counter
  double speed_hz = 0.0;          ///< speed (command) now, Hz
};

/// The finished sweep as the event thread reads it (valid between ready() and release()).
struct SweepCaptureView {
  uint32_t samples_per_period = 0, settle_periods = 0, recorded_periods = 0;
  std::span<const uint32_t> bins;
  double amplitude_a = 0.0, crest_factor = 0.0;
  std::array<uint8_t, 4> axes{};          ///< the order swept
  uint8_t axes_done = 0;                  ///< axes completely recorded (the first axes_done of `axes`)
  bool aborted = false;
  SweepAbort abort_reason = SweepAbort::none;
  int64_t start_t_ns = 0;                 ///< HAL time of the first recorded sample, ns
  uint64_t start_seq = 0;                 ///< its loop period counter
  int64_t end_t_ns = 0;                   ///< HAL time of the last period of the sweep, ns
  double speed_hz = 0.0;                  ///< speed at the start, Hz
  /// Channel `ch` (0 e, 1 u_c, 2 u, 3 y) of swept axis `i` (< axes_done): recorded_periods * N samples.
  std::span<const float> channel(uint32_t i, uint32_t ch) const {
    const size_t n = static_cast<size_t>(recorded_periods) * samples_per_period;
    return data.subspan((static_cast<size_t>(i) * 4 + ch) * n, n);
  }
  std::span<const float> data;
};

class SweepGenerator {
 public:
  SweepGenerator() { published_.store(status()); }
  /// Configure time (allocates the period table and the record buffer). `bias_current_a`: the
  /// amplitude's reference; `abort_orbit_m`: the orbit radius that aborts. Returns "" or why
  /// the sweep cannot run (then every start is refused, reason amplitude_limit or
  /// not_configured). Resets the counters.
  std::string configure(const SweepParams& p, double rate_hz, double bias_current_a, double abort_orbit_m);
  /// Back to idle, counters cleared, requests dropped (configure time).
  void reset();

  /// Any thread: request a start / an abort (taken at the next period).
  void request_start() { start_req_.store(true, std::memory_order_release); }
  void request_abort() { abort_req_.store(true, std::memory_order_release); }
  /// Any thread: count a refusal decided outside the loop (e.g. not armed).
  void count_refusal(SweepRefusal r);
  /// Any thread: the refusal counter and the last reason, now (status() is the loop's view).
  uint32_t refusals() const { return refusals_.load(std::memory_order_relaxed); }
  SweepRefusal last_refusal() const { return static_cast<SweepRefusal>(last_refusal_.load(std::memory_order_relaxed)); }
  /// Why a start would be refused now by the configuration alone (none: it could run).
  SweepRefusal config_refusal() const { return config_refusal_; }

  /// [RT] Nothing to do this period (idle, no request, no record handed back): the loop may
  /// skip begin_step()/end_step(). Plain loads only.
  bool quiet() const {
    return state_ == SweepState::idle && !start_req_.load(std::memory_order_relaxed) &&
           !abort_req_.load(std::memory_order_relaxed);
  }
  /// [RT] Start of the period: take requests, check limits. Returns the excitation (A) to add
  /// to control axis `axis` (set to -1 and 0.0 returned when none is excited).
  double begin_step(const SweepInputs& in, int& axis);
  /// [RT] After the demand is formed: u_c, u (what goes to the amplifier) and y of the excited
  /// axis (ignored when begin_step returned axis -1). Records and advances.
  void end_step(double uc_a, double u_a, double y_m);
  /// [RT] Progress and counters, the loop's own view (loop thread only).
  SweepStatus status() const;
  /// [RT] Publish status() for other threads if it changed since the last publication (a
  /// start, a settle or recorded period done, an axis done, the end, the record handed back;
  /// refusals are read live by published_status()). The loop calls it after begin_step()/end_step(); a quiet generator has
  /// nothing to publish, so the idle loop does not publish the sweep status at all.
  void publish_status() {
    if (!changed_) return;
    changed_ = false;
    published_.store(status());
  }
  /// Any thread: the latest published status, with the refusal counter and reason as of now
  /// (refusals are also counted outside the loop).
  SweepStatus published_status() const {
    SweepStatus s = published_.load();
    s.refusals = refusals_.load(std::memory_order_relaxed);
    s.last_refusal = static_cast<SweepRefusal>(last_refusal_.load(std::memory_order_relaxed));
    return s;
  }

  /// Event thread: a finished sweep waits; its view; hand the buffer back.
  bool ready() const { return ready_.load(std::memory_order_acquire); }
  SweepCaptureView view() const;
  void release() {
    ready_.store(false, std::memory_order_relaxed);
    released_.store(true, std::memory_order_release);
  }

  const MultisineDesign& design() const { return design_; }
  double amplitude_a() const { return amplitude_a_; }
  const SweepParams& params() const { return p_; }
  double abort_orbit_m() const { return abort_orbit_m_; }
  size_t buffer_bytes() const { return buffer_.size() * sizeof(float); }

 private:
  void finish(SweepAbort reason);
  SweepParams p_{};
  MultisineDesign design_;
  double amplitude_a_ = 0.0;
  double abort_orbit_m_ = 0.0;
  SweepRefusal config_refusal_ = SweepRefusal::not_configured;
  std::array<uint8_t, 4> order_{};
  uint8_t n_axes_ = 0;
  std::vector<float> buffer_;
  // Loop state.
  SweepState state_ = SweepState::idle;
  uint32_t k_ = 0, period_ = 0;
  uint8_t axis_i_ = 0, axes_done_ = 0;
  bool aborted_ = false;
  SweepAbort abort_reason_ = SweepAbort::none;
  int64_t start_t_ns_ = 0, end_t_ns_ = 0, t_ns_ = 0;
  uint64_t start_seq_ = 0, seq_ = 0;
  double speed_hz_ = 0.0;
  bool start_stamped_ = false;
  uint32_t started_ = 0, completed_ = 0, aborts_ = 0;
  SweepAbort last_abort_ = SweepAbort::none;
  bool changed_ = false;                  ///< status() differs from the published one
  SeqLock<SweepStatus> published_;
  // Shared with other threads.
  std::atomic<bool> start_req_{false}, abort_req_{false};
  std::atomic<bool> ready_{false}, released_{false};
  std::atomic<uint32_t> refusals_{0};
  std::atomic<uint8_t> last_refusal_{0};
};

}  // namespace amb::fw
