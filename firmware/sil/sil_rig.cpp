#include "firmware/sil/sil_rig.hpp"

#include <chrono>
#include <thread>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace amb::sil {

SilRig::SilRig(const board::BoardConfig& board, SilOptions options) : board_(board), options_(options) {
  build(make_board_plant(board, options.noise_seed));
}

SilRig::SilRig(const board::BoardConfig& board, std::unique_ptr<model::Plant> plant, SilOptions options)
    : board_(board), options_(options) {
  build(std::move(plant));
}

SilRig::~SilRig() { analysis_thread_.stop(); }

void SilRig::build(std::unique_ptr<model::Plant> plant) {
  plant->reset(options_.start_levitated, 0.0);
  sim_ = std::make_unique<hal::sim::SimRig>(std::move(plant), options_.tachometer);
  // The board's computation and transport delay: the demand acts that long after its sample.
  sim_->set_demand_delay_ns(std::llround(board_.loop_delay_periods / board_.rate_hz * 1e9));
  sup_.configure(board_);
  if (options_.analysis != SilAnalysis::off && board_.tracker.enabled) {
    analysis_ = std::make_unique<fw::AnalysisTask>();
    if (std::string err = analysis_->configure(board_, &sup_); !err.empty())
      throw std::invalid_argument("board " + board_.name + ": analysis task: " + err);
    poll_every_ = std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(board_.tracker.poll_period_s * board_.rate_hz)));
    if (options_.analysis == SilAnalysis::thread) analysis_thread_.start(*analysis_, board_.tracker.poll_period_s);
  }
  rebind();
  sim_->set_paced(options_.paced);
}

void SilRig::rebind() {
  fanout_ = fw::SampleFanout{};
  fanout_.add(sink_);
  fanout_.add(analysis_.get());
  fw::SampleSink* s = fanout_.size() == 0 ? nullptr : (fanout_.size() == 1 && !analysis_ ? sink_ : &fanout_);
  loop_ = std::make_unique<fw::LoopRunner>(sim_->clock(), sim_->analog(), sim_->discrete(), sup_, s);
  // The simulated clock stands still while the loop works: the per-period stamps (sample in,
  // step done, demand written) read the host's monotonic clock instead.
  loop_->set_stamp_clock(&sim_->wall_clock());
}

SilRig::AnalysisDrain SilRig::drain_analysis(double timeout_s) {
  AnalysisDrain d;
  if (!analysis_ || options_.analysis != SilAnalysis::thread) return d;
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const auto until = t0 + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(timeout_s));
  d.queued_before = analysis_->queued_samples();
  d.behind_s = static_cast<double>(d.queued_before) / board_.rate_hz;
  // Empty ring, then one more completed poll: the sample popped last has been analysed too.
  while (analysis_->queued_samples() > 0 && clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const uint64_t polls = analysis_->status().polls;
  while (analysis_->status().polls == polls && clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  d.queued_after = analysis_->queued_samples();
  d.waited_s = std::chrono::duration<double>(clock::now() - t0).count();
  return d;
}

void SilRig::set_sink(fw::SampleSink* sink) {
  sink_ = sink;
  // Rebuild only the sink binding (the runner starts from the clock's present time).
  rebind();
}

void SilRig::periods(uint64_t n) {
  if (!analysis_ || options_.analysis != SilAnalysis::lockstep) {
    loop_->run_periods(n);
    return;
  }
  // Lock-step analysis: the same poll() the thread makes, every poll_period_s of simulated time.
  while (n > 0) {
    const uint64_t k = std::min(n, poll_every_ - since_poll_);
    loop_->run_periods(k);
    n -= k;
    since_poll_ += k;
    if (since_poll_ >= poll_every_) {
      since_poll_ = 0;
      analysis_->poll();
    }
  }
}

void SilRig::run_for(double seconds) {
  const auto n = static_cast<uint64_t>(std::llround(seconds / sup_.period_s()));
  if (!on_period) {
    periods(n);
    return;
  }
  for (uint64_t i = 0; i < n; ++i) {
    periods(1);
    on_period(sup_.status());
  }
}

bool SilRig::run_until(const std::function<bool(const fw::Status&)>& done, double timeout_s) {
  const double end = time_s() + timeout_s;
  while (time_s() < end) {
    periods(1);
    const fw::Status st = sup_.status();
    if (on_period) on_period(st);
    if (done(st)) return true;
  }
  return false;
}

}  // namespace amb::sil
