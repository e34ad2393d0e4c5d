#include "firmware/app/loop_runner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace amb::fw {

int LoopStats::bin_of(int64_t latency_ns) {
  if (latency_ns < k_linear_top_ns) return static_cast<int>(std::max<int64_t>(0, latency_ns) / k_bin_ns);
  int64_t lo = k_linear_top_ns;
  for (int o = 0; o < k_octaves; ++o, lo *= 2) {
    if (latency_ns < 2 * lo) return k_linear_bins + o * k_sub_bins + static_cast<int>((latency_ns - lo) * k_sub_bins / lo);
  }
  return k_bins - 1;
}

int64_t LoopStats::bin_upper_ns(int bin) {
  if (bin < k_linear_bins) return static_cast<int64_t>(bin + 1) * k_bin_ns;
  if (bin >= k_bins - 1) return std::numeric_limits<int64_t>::max();
  const int o = (bin - k_linear_bins) / k_sub_bins;
  const int s = (bin - k_linear_bins) % k_sub_bins;
  const int64_t lo = k_linear_top_ns << o;
  return lo + lo * (s + 1) / k_sub_bins;
}

namespace {
int64_t quantile_of(const std::array<uint64_t, LoopStats::k_bins>& hist, uint64_t periods, int64_t max_ns, double q) {
  const double target = q * static_cast<double>(periods);
  double acc = 0.0;
  for (int i = 0; i < LoopStats::k_bins; ++i) {
    acc += static_cast<double>(hist[static_cast<size_t>(i)]);
    if (acc >= target) return std::min(LoopStats::bin_upper_ns(i), max_ns);
  }
  return max_ns;
}
}  // namespace

int64_t LoopStats::latency_quantile_ns(double q) const { return quantile_of(latency_hist, periods, max_latency_ns, q); }

int64_t LoopStats::delay_quantile_ns(double q) const { return quantile_of(delay_hist, periods, max_delay_ns, q); }

LoopRunner::LoopRunner(hal::Clock& clock, hal::AnalogFrontEnd& afe, hal::DiscreteIo& dio,
                       Supervisor& sup, SampleSink* sink)
    : clock_(clock), afe_(afe), dio_(dio), sup_(sup), sink_(sink),
      period_ns_(static_cast<int64_t>(std::llround(sup.period_s() * 1e9))) {}

int64_t LoopRunner::run_one(int64_t deadline_ns) {
  const int64_t woke = clock_.wait_until_ns(deadline_ns);
  const int64_t latency = std::max<int64_t>(0, woke - deadline_ns);
  // Stamps: clock reads only (vDSO clock_gettime on a board), no other call in the period.
  hal::Clock& stamp = stamp_ ? *stamp_ : clock_;
  const int64_t t_woke = stamp_ ? stamp.now_ns() : woke;
  const bool ok = afe_.read(in_);
  const int64_t t_in = stamp.now_ns();
  const hal::DiscreteInputs din = dio_.read();
  sup_.step(in_, ok, din, out_, dout_);
  const int64_t t_step = stamp.now_ns();
  afe_.write(out_);
  const int64_t t_out = stamp.now_ns();
  dio_.write(dout_);
  if (sink_) sink_->on_sample(sup_.last_sample());
  const int64_t done = clock_.now_ns();

  ++stats_.periods;
  stats_.sum_latency_ns += static_cast<double>(latency);
  stats_.max_latency_ns = std::max(stats_.max_latency_ns, latency);
  stats_.max_work_ns = std::max(stats_.max_work_ns, done - woke);
  ++stats_.latency_hist[static_cast<size_t>(LoopStats::bin_of(latency))];
  const int64_t delay = latency + std::max<int64_t>(0, t_out - t_woke);
  stats_.max_read_ns = std::max(stats_.max_read_ns, t_in - t_woke);
  stats_.max_step_ns = std::max(stats_.max_step_ns, t_step - t_in);
  stats_.max_write_ns = std::max(stats_.max_write_ns, t_out - t_step);
  stats_.max_delay_ns = std::max(stats_.max_delay_ns, delay);
  stats_.sum_delay_ns += static_cast<double>(delay);
  ++stats_.delay_hist[static_cast<size_t>(LoopStats::bin_of(delay))];
  int64_t next = deadline_ns + period_ns_;
  if (done > next) {
    // Overrun: count it and skip the missed deadlines instead of bursting to catch up.
    ++stats_.overruns;
    const int64_t missed = (done - deadline_ns) / period_ns_;
    next = deadline_ns + (missed + 1) * period_ns_;
  }
  return next;
}

void LoopRunner::run_periods(uint64_t n) {
  if (next_deadline_ns_ < 0) next_deadline_ns_ = clock_.now_ns() + period_ns_;
  for (uint64_t i = 0; i < n; ++i) next_deadline_ns_ = run_one(next_deadline_ns_);
}

void LoopRunner::run_until(const std::atomic<bool>& stop) {
  if (next_deadline_ns_ < 0) next_deadline_ns_ = clock_.now_ns() + period_ns_;
  while (!stop.load(std::memory_order_relaxed)) next_deadline_ns_ = run_one(next_deadline_ns_);
}

}  // namespace amb::fw
