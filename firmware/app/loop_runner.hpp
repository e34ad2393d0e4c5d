#pragma once
// The fixed-step loop: wait for the absolute deadline -> read -> step -> write, with an
// overrun counter and a latency histogram. Works with any HAL backend: with `sim` the clock
// steps the plant in lockstep; with `linux` it sleeps with clock_nanosleep(TIMER_ABSTIME).
#include <array>
#include <atomic>
#include <cstdint>

#include "firmware/app/supervisor.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

/// Receives every loop sample (the capture ring). Called in the loop thread: must be [RT].
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  virtual void on_sample(const LoopSample& s) = 0;
};

/// Wake-up latency statistics (lateness of the wake-up against the absolute deadline).
/// The histogram is log-linear and fixed-size (no allocation, trivially copyable): 64 bins of
/// 2 us up to 128 us, then 16 bins per octave (6.25 % of the value or finer) up to
/// 128 us x 2^14 = 2.1 s, then one overflow bin. A quantile is the upper edge of its bin, never
/// above the largest latency seen, so p99 stays a real number on a loaded or emulated machine.
struct LoopStats {
  static constexpr int k_linear_bins = 64;
  static constexpr int64_t k_bin_ns = 2000;      ///< width of the linear bins, ns
  static constexpr int64_t k_linear_top_ns = k_linear_bins * k_bin_ns;  ///< 128 us
  static constexpr int k_sub_bins = 16;          ///< bins per octave above the linear range
  static constexpr int k_octaves = 14;           ///< octaves above it: up to 2.1 s
  static constexpr int k_bins = k_linear_bins + k_sub_bins * k_octaves + 1;  ///< last: overflow
  uint64_t periods = 0;
  uint64_t overruns = 0;                         ///< periods whose work ended after the next deadline
  int64_t max_latency_ns = 0;
  double sum_latency_ns = 0.0;
  int64_t max_work_ns = 0;                       ///< read+step+write duration, worst
  std::array<uint64_t, k_bins> latency_hist{};   ///< counts per bin (see bin_of)
  // The loop's own delay, per period (issue 38): the sample instant (the deadline) -> sample in
  // hand (read) -> step done -> demand handed to the front end (written). Wake-up latency
  // (loop clock) plus the work up to the write (stamp clock: the loop clock on a board, the
  // host's monotonic clock in simulation, where the loop clock stands still during the step).
  int64_t max_read_ns = 0;                       ///< woke -> sample in hand, worst
  int64_t max_step_ns = 0;                       ///< sample in hand -> step done, worst
  int64_t max_write_ns = 0;                      ///< step done -> demand written, worst
  int64_t max_delay_ns = 0;                      ///< sample instant -> demand written, worst
  double sum_delay_ns = 0.0;
  std::array<uint64_t, k_bins> delay_hist{};     ///< sample instant -> demand written, counts per bin
  double mean_latency_ns() const { return periods ? sum_latency_ns / static_cast<double>(periods) : 0.0; }
  double mean_delay_ns() const { return periods ? sum_delay_ns / static_cast<double>(periods) : 0.0; }
  /// Latency below which fraction `q` (0..1) of the periods woke up, from the histogram, ns:
  /// the upper edge of the bin that holds it, at most max_latency_ns.
  int64_t latency_quantile_ns(double q) const;
  /// Delay (sample instant -> demand written) below which fraction `q` of the periods wrote
  /// their demand, ns: the upper edge of its bin, at most max_delay_ns.
  int64_t delay_quantile_ns(double q) const;
  /// [RT] Histogram bin of a latency (ns, >= 0); bounded time, no allocation.
  static int bin_of(int64_t latency_ns);
  /// Upper edge of bin `bin`, ns (the overflow bin: INT64_MAX).
  static int64_t bin_upper_ns(int bin);
};

class LoopRunner {
 public:
  LoopRunner(hal::Clock& clock, hal::AnalogFrontEnd& afe, hal::DiscreteIo& dio, Supervisor& sup,
             SampleSink* sink = nullptr);
  /// Clock of the per-period stamps (read, step, write; see LoopStats). Default: the loop
  /// clock. A simulation passes a wall clock so the stamps measure the host's work. [configure]
  void set_stamp_clock(hal::Clock* clock) { stamp_ = clock; }
  /// Run `n` periods starting from the clock's present time.
  void run_periods(uint64_t n);
  /// Run until `stop` becomes true (checked once per period).
  void run_until(const std::atomic<bool>& stop);
  /// [RT] One period at the given deadline; returns the next deadline.
  int64_t run_one(int64_t deadline_ns);
  const LoopStats& stats() const { return stats_; }
  int64_t period_ns() const { return period_ns_; }
  const hal::AnalogOutputs& last_outputs() const { return out_; }

 private:
  hal::Clock& clock_;
  hal::Clock* stamp_ = nullptr;  // nullptr: clock_
  hal::AnalogFrontEnd& afe_;
  hal::DiscreteIo& dio_;
  Supervisor& sup_;
  SampleSink* sink_;
  int64_t period_ns_;
  int64_t next_deadline_ns_ = -1;
  hal::AnalogInputs in_{};
  hal::AnalogOutputs out_{};
  hal::DiscreteOutputs dout_{};
  LoopStats stats_{};
};

}  // namespace amb::fw
