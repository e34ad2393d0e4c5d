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
struct LoopStats {
  static constexpr int k_bins = 64;
  static constexpr int64_t k_bin_ns = 2000;      ///< histogram bin width, ns (last bin: overflow)
  uint64_t periods = 0;
  uint64_t overruns = 0;                         ///< periods whose work ended after the next deadline
  int64_t max_latency_ns = 0;
  double sum_latency_ns = 0.0;
  int64_t max_work_ns = 0;                       ///< read+step+write duration, worst
  std::array<uint64_t, k_bins> latency_hist{};   ///< counts per k_bin_ns bin
  double mean_latency_ns() const { return periods ? sum_latency_ns / static_cast<double>(periods) : 0.0; }
  /// Latency below which fraction `q` (0..1) of the periods woke up, from the histogram, ns.
  int64_t latency_quantile_ns(double q) const;
};

class LoopRunner {
 public:
  LoopRunner(hal::Clock& clock, hal::AnalogFrontEnd& afe, hal::DiscreteIo& dio, Supervisor& sup,
             SampleSink* sink = nullptr);
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
