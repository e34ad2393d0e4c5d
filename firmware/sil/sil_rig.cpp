#include "firmware/sil/sil_rig.hpp"

#include <cmath>

namespace amb::sil {

SilRig::SilRig(const board::BoardConfig& board, SilOptions options) : board_(board), options_(options) {
  build(make_board_plant(board, options.noise_seed));
}

SilRig::SilRig(const board::BoardConfig& board, std::unique_ptr<model::Plant> plant, SilOptions options)
    : board_(board), options_(options) {
  build(std::move(plant));
}

void SilRig::build(std::unique_ptr<model::Plant> plant) {
  plant->reset(options_.start_levitated, 0.0);
  sim_ = std::make_unique<hal::sim::SimRig>(std::move(plant), options_.tachometer);
  sup_.configure(board_);
  loop_ = std::make_unique<fw::LoopRunner>(sim_->clock(), sim_->analog(), sim_->discrete(), sup_, sink_);
  sim_->set_paced(options_.paced);
}

void SilRig::set_sink(fw::SampleSink* sink) {
  sink_ = sink;
  // The runner keeps its deadline; rebuild only the sink binding.
  auto next = std::make_unique<fw::LoopRunner>(sim_->clock(), sim_->analog(), sim_->discrete(), sup_, sink_);
  loop_ = std::move(next);
}

void SilRig::run_for(double seconds) {
  const auto n = static_cast<uint64_t>(std::llround(seconds / sup_.period_s()));
  if (!on_period) {
    loop_->run_periods(n);
    return;
  }
  for (uint64_t i = 0; i < n; ++i) {
    loop_->run_periods(1);
    on_period(sup_.status());
  }
}

bool SilRig::run_until(const std::function<bool(const fw::Status&)>& done, double timeout_s) {
  const double end = time_s() + timeout_s;
  while (time_s() < end) {
    loop_->run_periods(1);
    const fw::Status st = sup_.status();
    if (on_period) on_period(st);
    if (done(st)) return true;
  }
  return false;
}

}  // namespace amb::sil
