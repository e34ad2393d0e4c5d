#include "host-tools/core/replay/event_replay.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "hal/replay/replay_rig.hpp"
#include "host-tools/core/replay/replay_input.hpp"

namespace amb::host::replay {

namespace {
/// Keeps every replayed sample (pre-sized) and forwards it to the capture.
class RecordingSink final : public fw::SampleSink {
 public:
  RecordingSink(std::vector<fw::LoopSample>& out, fw::FloatingCapture& capture) : out_(out), capture_(capture) {}
  void on_sample(const fw::LoopSample& s) override {
    if (n_ < out_.size()) out_[n_++] = s;
    capture_.on_sample(s);
  }
  size_t count() const { return n_; }

 private:
  std::vector<fw::LoopSample>& out_;
  fw::FloatingCapture& capture_;
  size_t n_ = 0;
};

bool energised(const fw::LoopSample& s) {
  const auto st = static_cast<fw::State>(s.state);
  return st == fw::State::levitating || st == fw::State::running;
}
}  // namespace

std::string first_diagnosis_difference(const fw::diag::Diagnosis& a, const fw::diag::Diagnosis& b) {
  auto same = [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); };
  if (a.type != b.type) return "type";
  if (!same(a.confidence, b.confidence)) return "confidence";
  if (a.cutoff_channels != b.cutoff_channels) return "cutoff_channels";
  for (size_t i = 0; i < 4; ++i)
    if (!same(a.current_factor[i], b.current_factor[i])) return "current_factor";
  if (!same(a.disturbance_frequency_hz, b.disturbance_frequency_hz)) return "disturbance_frequency_hz";
  if (!same(a.disturbance_amplitude_a, b.disturbance_amplitude_a)) return "disturbance_amplitude_a";
  if (a.disturbance_channels != b.disturbance_channels) return "disturbance_channels";
  if (!same(a.current_lead_s, b.current_lead_s)) return "current_lead_s";
  if (!same(a.speed_hz, b.speed_hz)) return "speed_hz";
  for (size_t i = 0; i < 2; ++i) {
    if (!same(a.radius_1x_start_m[i], b.radius_1x_start_m[i])) return "radius_1x_start_m";
    if (!same(a.radius_1x_end_m[i], b.radius_1x_end_m[i])) return "radius_1x_end_m";
    if (!same(a.centre_shift_m[i], b.centre_shift_m[i])) return "centre_shift_m";
  }
  if (!same(a.misalignment_direction_deg, b.misalignment_direction_deg)) return "misalignment_direction_deg";
  if (a.misalignment_plane != b.misalignment_plane) return "misalignment_plane";
  if (a.summary != b.summary) return "summary";
  return {};
}

ReplayResult replay_event(const fw::EventRecord& ev, const board::BoardConfig& board, const ReplayOptions& o) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (ev.samples.empty()) throw std::runtime_error("the event holds no samples: nothing to replay");
  ReplayResult r;
  r.board = board.name + " (" + board.source + ")";
  const size_t n = ev.samples.size();
  const size_t trig = ev.meta.trigger_index;

  fw::Supervisor sup;
  sup.configure(board);

  // Where the controller state is provably the board's.
  size_t compare_from = k_no_index;
  if (ev.samples.front().seq == 0) {
    r.mode = "from_configure";
    compare_from = 0;
    r.compare_from_reason = "the window starts at configure (seq 0): a fresh supervisor has the board's state";
    r.warm_up.reached = true;
    r.warm_up.note = "none needed";
  } else {
    r.warm_up = warm_up(sup, ev.samples.front(), o.max_warm_up_steps);
    for (size_t i = 0; i < n; ++i)
      if (!energised(ev.samples[i])) {
        compare_from = i;
        break;
      }
    if (compare_from == k_no_index) {
      r.mode = "not_reproducible";
      r.compare_from_reason = "the window starts mid-run and the amplifiers stay on throughout: the controller state "
                              "(integrators, filters) at its start is not in the event (AMBE v1 has no snapshot)";
    } else {
      r.mode = "after_warm_up";
      r.compare_from_reason = "the window starts mid-run (controller state not in the event); from sample " +
                              std::to_string(compare_from) +
                              " the amplifiers are off, so outputs no longer depend on the controller state and "
                              "the next lift-off resets it";
    }
  }

  // The replay backend, the loop runner and a fresh capture like the board's.
  hal::replay::ReplayRig rig;
  rig.configure(replay_samples(ev.samples), static_cast<int64_t>(std::llround(1e9 / board.rate_hz)));
  fw::FloatingCapture capture;
  fw::configure_capture(capture, board);
  r.replayed.assign(n, fw::LoopSample{});
  RecordingSink sink(r.replayed, capture);
  fw::LoopRunner loop(rig.clock(), rig.analog(), rig.discrete(), sup, &sink);

  fw::Status st = sup.status();
  const size_t every = std::max<size_t>(1, n / 100);
  for (size_t i = 0; i < n; ++i) {
    const fw::Command cmd = i == 0 ? command_for_transition(st.state, st.phase, ev.samples[0])
                                   : command_for_transition(ev.samples[i - 1], ev.samples[i]);
    if (cmd != fw::Command::none && sup.post(cmd)) ++r.commands_posted;
    const TrackedUpdate tu = tracked_update(ev.samples[i]);
    sup.publish_tracked_speed(tu.speed_hz, tu.confidence, tu.lost);
    loop.run_periods(1);
    if (o.progress && (i % every == 0 || i + 1 == n)) o.progress(static_cast<double>(i + 1) / static_cast<double>(n));
  }

  r.comparison = compare_samples(ev.samples, r.replayed, compare_from, trig, o.max_listed_differences);

  // Triggers: the replayed capture against the recording.
  TriggerComparison& tc = r.trigger;
  tc.recorded_index = trig;
  tc.recorded_cause_mask = ev.meta.cause_mask;
  tc.recorded_cause = fw::to_string(ev.meta.cause);
  const fw::FrozenEvent* fe = capture.take();
  if (fe != nullptr) {
    tc.replayed_frozen = true;
    // The replayed capture saw the window from its first sample: its trigger sample's index
    // in the recorded window is the number of samples before it.
    const uint64_t first_seq = r.replayed.front().seq;
    tc.replayed_index = static_cast<size_t>(fe->header.trigger_seq - first_seq);
    tc.replayed_cause_mask = fe->header.cause_mask;
    tc.replayed_cause = fw::to_string(fe->header.cause);
    tc.reproduced = tc.replayed_index == tc.recorded_index && tc.replayed_cause_mask == tc.recorded_cause_mask;

    // Phase B re-run on the replayed capture.
    const fw::EventRecord replayed_record = fw::make_event_record(*fe, board, ev.meta.event_number);
    DiagnosisComparison& dc = r.diagnosis;
    dc.replayed = fw::diag::diagnose(fw::diagnosis_input(replayed_record));
    dc.recorded_available = ev.has_diagnosis;
    dc.recorded = ev.has_diagnosis ? ev.diagnosis : fw::diag::diagnose(fw::diagnosis_input(ev));
    dc.first_difference = first_diagnosis_difference(dc.recorded, dc.replayed);
    dc.type_reproduced = dc.recorded.type == dc.replayed.type;
    dc.bit_exact = dc.first_difference.empty();
    capture.release(fe);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace amb::host::replay
