#pragma once
// What the running board measures of its own budget (memory from /proc, CPU time of the loop
// and analysis threads, start-up time), published by the service's supervision thread every
// second through a SeqLock and served on the supervisory link (registers 0x0700..). Measured
// outside the loop step: the loop only runs; another thread reads its CPU clock.
#include <array>
#include <cstddef>
#include <cstdint>

namespace amb::fw {

/// Trivially copyable snapshot (SeqLock).
struct RuntimeBudget {
  uint64_t locked_kb = 0;          ///< VmLck, kB
  uint64_t resident_kb = 0;        ///< VmRSS, kB
  uint64_t peak_resident_kb = 0;   ///< VmHWM, kB
  double loop_cpu_share = -1.0;    ///< loop thread's CPU time / wall time over the window (1 = one CPU); < 0 not yet measured
  double analysis_cpu_share = -1.0;///< the analysis thread's, same window; < 0 not running
  double window_s = 0.0;           ///< wall time the shares cover, s
  int64_t start_to_ready_ns = -1;  ///< process start to READY (loop running), ns; < 0 not yet
};

/// CPU share of one thread over a sliding window of the last `N` - 1 samples (one sample per
/// call of add(), e.g. once a second: N = 21 gives 20 s). Fixed size, no allocation.
template <size_t N = 21>
class CpuShareWindow {
 public:
  /// Record the thread's CPU time `cpu_ns` at wall time `wall_ns` (any monotonic clock).
  void add(int64_t wall_ns, int64_t cpu_ns) {
    wall_[next_] = wall_ns;
    cpu_[next_] = cpu_ns;
    next_ = (next_ + 1) % N;
    if (count_ < N) ++count_;
  }
  /// CPU time / wall time between the oldest and the newest sample; -1 with fewer than two.
  double share() const {
    if (count_ < 2) return -1.0;
    const size_t newest = (next_ + N - 1) % N, oldest = count_ < N ? 0 : next_;
    const int64_t dw = wall_[newest] - wall_[oldest];
    return dw > 0 ? static_cast<double>(cpu_[newest] - cpu_[oldest]) / static_cast<double>(dw) : -1.0;
  }
  /// Wall time the share covers, s.
  double window_s() const {
    if (count_ < 2) return 0.0;
    const size_t newest = (next_ + N - 1) % N, oldest = count_ < N ? 0 : next_;
    return static_cast<double>(wall_[newest] - wall_[oldest]) * 1e-9;
  }

 private:
  std::array<int64_t, N> wall_{}, cpu_{};
  size_t next_ = 0, count_ = 0;
};

}  // namespace amb::fw
