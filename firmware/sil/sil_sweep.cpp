#include "firmware/sil/sil_sweep.hpp"

namespace amb::sil {

SilSweepBench::SilSweepBench(const board::BoardConfig& board, uint64_t noise_seed)
    : storage_(std::max<uint64_t>(board.capture.storage_capacity_bytes, 1ull << 20) + (256ull << 20)), board_(board) {
  SilOptions so;
  so.noise_seed = noise_seed;
  rig_ = std::make_unique<SilRig>(board_, so);
  capture_ = std::make_unique<fw::FloatingCapture>();
  fw::configure_capture(*capture_, board_);
  rig_->set_sink(capture_.get());
  fw::WriterOptions wo;
  wo.run_diagnosis = false;  // drop events during a sweep are not its subject
  writer_ = std::make_unique<fw::EventWriter>(*capture_, storage_, board_, wo);
  writer_->set_sweep_source(&rig_->supervisor().sweep());
  writer_->on_sweep = [this](const fw::SweepEvent&, const std::string& name, bool stored) {
    last_sweep_name_ = name;
    last_stored_ = stored;
  };
}

bool SilSweepBench::levitate(bool spin, std::string& error) {
  fw::Supervisor& sup = rig_->supervisor();
  auto at = [](fw::Phase p) { return [p](const fw::Status& s) { return s.phase == p || s.state == fw::State::fault; }; };
  rig_->run_for(0.01);
  sup.post(fw::Command::levitate);
  if (!rig_->run_until(at(fw::Phase::levitated), 20.0) || sup.state() == fw::State::fault) {
    error = std::string("lift-off failed (fault: ") + fw::to_string(sup.status().fault) + ")";
    return false;
  }
  if (spin) {
    sup.post(fw::Command::run);
    if (!rig_->run_until(at(fw::Phase::at_speed), 600.0) || sup.state() == fw::State::fault) {
      error = std::string("spin-up failed (fault: ") + fw::to_string(sup.status().fault) + ")";
      return false;
    }
  }
  return true;
}

SilSweepOutcome SilSweepBench::run_sweep(double timeout_s, const SilSweepOptions& o) {
  SilSweepOutcome out;
  fw::Supervisor& sup = rig_->supervisor();
  const uint32_t started_before = sup.status().sweep.started;
  last_sweep_name_.clear();
  last_stored_ = false;
  // Take the request (one period), then run in slices, polling the writer as its thread would.
  rig_->run_for(1.0 / board_.rate_hz);
  out.started = sup.status().sweep.started > started_before;
  if (!out.started) {
    out.status = sup.status().sweep;
    out.error = std::string("sweep refused: ") + fw::to_string(out.status.last_refusal);
    return out;
  }
  const double end = rig_->time_s() + timeout_s;
  double next_progress = rig_->time_s();
  const double slice = std::max(1.0 / board_.rate_hz, 0.01);
  while (rig_->time_s() < end) {
    rig_->run_for(slice);
    writer_->poll();
    const fw::SweepStatus s = sup.status().sweep;
    if (o.progress && rig_->time_s() >= next_progress) {
      o.progress(s, rig_->time_s());
      next_progress += o.progress_every_s;
    }
    if (!last_sweep_name_.empty()) break;
  }
  rig_->run_for(1.0 / board_.rate_hz);  // the loop takes the buffer back
  out.status = sup.status().sweep;
  if (last_sweep_name_.empty()) {
    out.error = "the sweep did not end within " + std::to_string(timeout_s) + " s of simulated time";
    return out;
  }
  out.event_name = last_sweep_name_;
  if (!last_stored_) {
    out.error = "sweep event " + last_sweep_name_ + " not stored: " + writer_->last_error();
    return out;
  }
  std::string err;
  if (!storage_.read(last_sweep_name_, out.event_bytes, err)) {
    out.error = "sweep event " + last_sweep_name_ + " cannot be read back: " + err;
    return out;
  }
  out.stored = true;
  return out;
}

SilSweepOutcome run_sil_sweep(const board::BoardConfig& board, const SilSweepOptions& o) {
  SilSweepBench bench(board, o.noise_seed);
  SilSweepOutcome out;
  if (!bench.levitate(o.spin, out.error)) return out;
  bench.supervisor().request_sweep_start();
  return bench.run_sweep(o.timeout_s, o);
}

}  // namespace amb::sil
