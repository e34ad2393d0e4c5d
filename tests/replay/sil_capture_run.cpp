#include "tests/replay/sil_capture_run.hpp"

#include <stdexcept>

#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "hal/sim/sim_rig.hpp"

namespace amb::test {

namespace {
/// The sim front end, rounded to float32 (see the header).
class Float32FrontEnd final : public hal::AnalogFrontEnd {
 public:
  explicit Float32FrontEnd(hal::AnalogFrontEnd& inner) : inner_(inner) {}
  bool read(hal::AnalogInputs& in) override {
    const bool ok = inner_.read(in);
    if (ok) {
      for (double& d : in.displacement_m) d = static_cast<float>(d);
      for (double& c : in.coil_current_a) c = static_cast<float>(c);
      if (in.tach_speed_hz >= 0.0) in.tach_speed_hz = static_cast<float>(in.tach_speed_hz);
    }
    return ok;
  }
  void write(const hal::AnalogOutputs& out) override { inner_.write(out); }

 private:
  hal::AnalogFrontEnd& inner_;
};

class FanOut final : public fw::SampleSink {
 public:
  FanOut(fw::SampleSink& a, fw::SampleSink& b) : a_(a), b_(b) {}
  void on_sample(const fw::LoopSample& s) override {
    a_.on_sample(s);
    b_.on_sample(s);
  }

 private:
  fw::SampleSink& a_;
  fw::SampleSink& b_;
};

std::vector<uint8_t> first_event(hal::sim::MemoryStorage& storage) {
  std::vector<uint8_t> bytes;
  std::string err;
  const auto names = storage.list();
  if (names.empty()) throw std::runtime_error("no event stored");
  if (!storage.read(names.front(), bytes, err)) throw std::runtime_error(err);
  return bytes;
}
}  // namespace

CaptureRunResult run_sil_capture(const CaptureRunOptions& o) {
  CaptureRunResult res;
  board::BoardConfig board = board::load_board("bath-amb-rig");
  board.capture.post_trigger_s = o.post_trigger_s;
  if (o.tracker_speed_source) {
    board.tracker.enabled = true;
    board.tracker.speed_source = fw::SpeedSource::tracker;
  }
  board::BoardConfig board_full = board;
  board_full.capture.pre_trigger_s = o.full_pre_trigger_s;
  res.board = board;

  hal::sim::SimRig sim(sil::make_board_plant(board, 1), false);
  sim.plant().reset(false, 0.0);
  Float32FrontEnd afe(sim.analog());
  fw::Supervisor sup;
  sup.configure(board);
  fw::FloatingCapture cap_default, cap_full;
  fw::configure_capture(cap_default, board);
  fw::configure_capture(cap_full, board_full);
  FanOut sink(cap_default, cap_full);
  fw::LoopRunner loop(sim.clock(), afe, sim.discrete(), sup, &sink);
  const double dt = sup.period_s();
  uint64_t periods = 0;
  // One loop period; with tracker_speed_source the tracker stand-in publishes first.
  auto step = [&]() {
    const double t = static_cast<double>(periods) * dt;
    if (o.tracker_speed_source && periods % 50 == 0 && !(t >= 2.0 && t < 2.8)) {
      const bool lost = t >= 1.0 && t < 1.3;
      sup.publish_tracked_speed(sim.plant().outputs().spin_speed_hz * 1.001, lost ? 0.3 : 0.87, lost);
    }
    loop.run_periods(1);
    ++periods;
  };
  auto run_until = [&](auto&& done, double timeout_s) {
    for (double t = 0.0; t < timeout_s; t += dt) {
      step();
      if (done(sup.status())) return true;
    }
    return false;
  };
  auto run_for = [&](double s) {
    for (uint64_t k = static_cast<uint64_t>(s / dt); k > 0; --k) step();
  };

  run_for(0.05);  // resting on the touchdown bearings
  sup.post(fw::Command::levitate);
  if (!run_until([](const fw::Status& s) { return s.phase == fw::Phase::levitated; }, 5.0))
    throw std::runtime_error("SIL: did not levitate");
  sup.post(fw::Command::run);
  if (!run_until([](const fw::Status& s) { return s.phase == fw::Phase::at_speed; }, 10.0))
    throw std::runtime_error("SIL: did not reach speed");
  run_for(o.hold_s);
  res.cut_time_s = static_cast<double>(sim.time_ns()) * 1e-9;
  model::PlantFaults cut;
  cut.current_factor = {0.0, 0.0, 0.0, 0.0};
  sim.plant().set_faults(cut);
  // Until both captures froze their windows.
  if (!run_until([&](const fw::Status&) { return cap_default.counters().events_frozen > 0 && cap_full.counters().events_frozen > 0; },
                 o.post_trigger_s + 1.0))
    throw std::runtime_error("SIL: the captures did not freeze a window");

  // Store the events as the board does (Phase B, AMBE v1 encoding, storage).
  hal::sim::MemoryStorage store_default(256ull << 20), store_full(256ull << 20);
  fw::EventWriter w_default(cap_default, store_default, board);
  fw::EventWriter w_full(cap_full, store_full, board_full);
  w_default.poll();
  w_full.poll();
  res.event_default = first_event(store_default);
  res.event_full_history = first_event(store_full);
  res.log = std::string("final state ") + fw::to_string(sup.status().state) + " (" + fw::to_string(sup.status().fault) + ")";
  return res;
}

const CaptureRunResult& sil_capture() {
  static const CaptureRunResult r = run_sil_capture();
  return r;
}

}  // namespace amb::test
