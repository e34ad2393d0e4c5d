#include "hal/replay/replay_rig.hpp"

#include <stdexcept>
#include <string>

namespace amb::hal::replay {

void ReplayRig::configure(std::vector<ReplaySample> samples, int64_t period_ns) {
  if (samples.empty()) throw std::invalid_argument("replay: the recording has no samples");
  if (period_ns <= 0) throw std::invalid_argument("replay: period_ns must be > 0");
  for (size_t i = 1; i < samples.size(); ++i)
    if (samples[i].analog.t_ns < samples[i - 1].analog.t_ns)
      throw std::invalid_argument("replay: sample " + std::to_string(i) + " is earlier than sample " +
                                  std::to_string(i - 1) + " (t_ns " + std::to_string(samples[i].analog.t_ns) +
                                  " < " + std::to_string(samples[i - 1].analog.t_ns) + ")");
  samples_ = std::move(samples);
  outputs_.assign(samples_.size(), ReplayOutputs{});
  period_ns_ = period_ns;
  cursor_ = -1;
  past_end_ = false;
  counters_ = {};
}

int64_t ReplayClock::now_ns() {
  if (rig_.samples_.empty()) return 0;
  if (rig_.cursor_ < 0) return rig_.samples_.front().analog.t_ns - rig_.period_ns_;
  return rig_.samples_[static_cast<size_t>(rig_.cursor_)].analog.t_ns;
}

int64_t ReplayClock::wait_until_ns(int64_t /*deadline_ns*/) {
  // The recording, not the deadline, says when the next sample was taken.
  if (rig_.cursor_ + 1 < static_cast<std::ptrdiff_t>(rig_.samples_.size())) {
    ++rig_.cursor_;
    ++rig_.counters_.periods;
  } else {
    rig_.past_end_ = true;
  }
  return now_ns();
}

bool ReplayAnalogFrontEnd::read(AnalogInputs& in) {
  if (rig_.past_end_ || !rig_.in_range()) {
    ++rig_.counters_.reads_past_end;
    return false;
  }
  // A period without a valid sample leaves `in` as it was, as a real front end does: the
  // firmware recorded the stale timestamp and keeps its last good position.
  const ReplaySample& s = rig_.samples_[static_cast<size_t>(rig_.cursor_)];
  if (!s.read_ok) return false;
  in = s.analog;
  return true;
}

void ReplayAnalogFrontEnd::write(const AnalogOutputs& out) {
  if (rig_.past_end_ || !rig_.in_range()) {
    ++rig_.counters_.writes_past_end;
    return;
  }
  ReplayOutputs& o = rig_.outputs_[static_cast<size_t>(rig_.cursor_)];
  o.analog = out;
  o.analog_written = true;
}

DiscreteInputs ReplayDiscreteIo::read() {
  if (rig_.past_end_ || !rig_.in_range()) return DiscreteInputs{};
  return rig_.samples_[static_cast<size_t>(rig_.cursor_)].discrete;
}

void ReplayDiscreteIo::write(const DiscreteOutputs& out) {
  if (rig_.past_end_ || !rig_.in_range()) return;
  ReplayOutputs& o = rig_.outputs_[static_cast<size_t>(rig_.cursor_)];
  o.discrete = out;
  o.discrete_written = true;
}

}  // namespace amb::hal::replay
