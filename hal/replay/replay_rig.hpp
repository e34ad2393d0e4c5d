#pragma once
// The `replay` HAL backend: feeds a recorded capture through the firmware sample by sample.
// The recording is preloaded at configure (plain samples, no firmware types); the loop then
// steps through it: waiting for a deadline moves to the next recorded sample and returns its
// recorded timestamp, read() returns that sample's displacements and coil currents, the
// discrete inputs reproduce its recorded flags, and write() records what the firmware
// demanded at that sample into a table allocated at configure.
//
// Real-time side ([RT] in hal/interfaces.hpp): read/write/wait do not allocate, lock, throw
// or make system calls. Past the end of the recording the clock stays on the last sample,
// read() reports no sample and the overrun is counted (never thrown).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hal/interfaces.hpp"

namespace amb::hal::replay {

/// One recorded loop period, as the replay feeds it to the firmware.
struct ReplaySample {
  AnalogInputs analog;        ///< analog.t_ns: recorded HAL time of the sample, ns (non-decreasing; a
                              ///< period without a valid sample repeats the last good time)
  bool read_ok = true;        ///< false: the front end had no valid sample in this period
  DiscreteInputs discrete;    ///< recorded discrete inputs (landing request, external trigger, amplifier fault)
};

/// What the firmware wrote in one replayed period.
struct ReplayOutputs {
  AnalogOutputs analog;       ///< current demands, amplifier enable, speed command
  DiscreteOutputs discrete;   ///< amplifier enable, watchdog, status lines
  bool analog_written = false;
  bool discrete_written = false;
};

/// Counters since configure.
struct ReplayCounters {
  uint64_t periods = 0;           ///< samples stepped to
  uint64_t reads_past_end = 0;    ///< reads after the recording ended (answered "no sample")
  uint64_t writes_past_end = 0;   ///< writes after the recording ended (dropped)
};

class ReplayRig;

class ReplayClock final : public Clock {
 public:
  explicit ReplayClock(ReplayRig& rig) : rig_(rig) {}
  /// [RT] Time of the current sample, ns (before the first: one period before it).
  int64_t now_ns() override;
  /// [RT] Step to the next recorded sample, whatever the deadline; returns its recorded time.
  int64_t wait_until_ns(int64_t deadline_ns) override;

 private:
  ReplayRig& rig_;
};

class ReplayAnalogFrontEnd final : public AnalogFrontEnd {
 public:
  explicit ReplayAnalogFrontEnd(ReplayRig& rig) : rig_(rig) {}
  /// [RT] The current sample's recorded inputs; false (and `in` untouched) where the
  /// recording had no valid sample.
  bool read(AnalogInputs& in) override;
  /// [RT] Record the firmware's demands for the current sample.
  void write(const AnalogOutputs& out) override;

 private:
  ReplayRig& rig_;
};

class ReplayDiscreteIo final : public DiscreteIo {
 public:
  explicit ReplayDiscreteIo(ReplayRig& rig) : rig_(rig) {}
  /// [RT] The current sample's recorded discrete inputs.
  DiscreteInputs read() override;
  /// [RT] Record the firmware's discrete outputs for the current sample.
  void write(const DiscreteOutputs& out) override;

 private:
  ReplayRig& rig_;
};

/// Owns the recording and the table of outputs; hands out the HAL objects.
class ReplayRig {
 public:
  /// Preload `samples` (allocates the output table). `period_ns`: the loop period, ns, used
  /// for the clock's time before the first sample. Throws std::invalid_argument if the
  /// recording is empty, times decrease (names the index) or period_ns <= 0.
  void configure(std::vector<ReplaySample> samples, int64_t period_ns);

  Clock& clock() { return clock_; }
  AnalogFrontEnd& analog() { return afe_; }
  DiscreteIo& discrete() { return dio_; }

  size_t size() const { return samples_.size(); }
  /// Index of the sample the loop is at (-1 before the first wait).
  std::ptrdiff_t cursor() const { return cursor_; }
  /// True once every recorded sample has been stepped to.
  bool finished() const { return cursor_ + 1 >= static_cast<std::ptrdiff_t>(samples_.size()); }
  std::span<const ReplaySample> samples() const { return samples_; }
  /// What the firmware wrote, one entry per recorded sample (unwritten entries flagged).
  std::span<const ReplayOutputs> outputs() const { return outputs_; }
  const ReplayCounters& counters() const { return counters_; }

 private:
  friend class ReplayClock;
  friend class ReplayAnalogFrontEnd;
  friend class ReplayDiscreteIo;
  bool in_range() const { return cursor_ >= 0 && cursor_ < static_cast<std::ptrdiff_t>(samples_.size()); }

  std::vector<ReplaySample> samples_;
  std::vector<ReplayOutputs> outputs_;
  int64_t period_ns_ = 100000;
  std::ptrdiff_t cursor_ = -1;
  bool past_end_ = false;
  ReplayCounters counters_{};
  ReplayClock clock_{*this};
  ReplayAnalogFrontEnd afe_{*this};
  ReplayDiscreteIo dio_{*this};
};

}  // namespace amb::hal::replay
