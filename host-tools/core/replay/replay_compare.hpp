#pragma once
// Compare a replayed capture with the recorded one, sample by sample and bit for bit: the
// controller outputs (current_demand_a per axis, speed_command_hz), the lifecycle (state,
// phase, fault), the flags and the sample time. From `compare_from` on every mismatch
// counts; before it (the warm-up part) differences are summarised, not counted.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "firmware/app/loop_sample.hpp"

namespace amb::host::replay {

inline constexpr size_t k_no_index = std::numeric_limits<size_t>::max();

/// One differing value.
struct SampleDifference {
  size_t index = 0;            ///< sample index in the recorded window
  int64_t t_ns = 0;            ///< recorded HAL time of the sample, ns
  double t_from_trigger_s = 0; ///< time relative to the trigger sample, s
  std::string channel;         ///< "current_demand_a[2]", "speed_command_hz", "state", "phase", "fault", "flags", "t_ns"
  double recorded = 0.0;       ///< recorded value (flags: the bit pattern as a number)
  double replayed = 0.0;       ///< replayed value
  double difference = 0.0;     ///< replayed - recorded (flags: recorded XOR replayed)
  int64_t ulps = 0;            ///< float channels: distance in units in the last place (else 0)
};

/// Per channel over the compared part.
struct ChannelSummary {
  std::string channel;
  uint64_t mismatches = 0;
  size_t first_index = k_no_index;   ///< first mismatching sample
  double max_abs_difference = 0.0;   ///< largest |replayed - recorded| (flags: 0)
};

struct ReplayComparison {
  size_t compare_from = k_no_index;  ///< first sample compared bit for bit (k_no_index: none)
  uint64_t compared_samples = 0;
  uint64_t mismatched_samples = 0;   ///< compared samples with at least one differing channel
  bool bit_exact = false;            ///< compared_samples > 0 and no mismatch
  std::vector<ChannelSummary> channels;
  std::vector<SampleDifference> differences;  ///< the first `max_listed` differences, in order
  // Before compare_from (warm-up; not counted).
  uint64_t warm_up_samples = 0;
  uint64_t warm_up_differing_samples = 0;
  double warm_up_max_demand_difference_a = 0.0;  ///< largest |replayed - recorded| demand, A
};

/// Compare `replayed` with `recorded` (same length and order). `trigger_index`: for the
/// time column. `max_listed`: differences kept in the list.
ReplayComparison compare_samples(std::span<const fw::LoopSample> recorded, std::span<const fw::LoopSample> replayed,
                                 size_t compare_from, size_t trigger_index, size_t max_listed = 20);

/// Human-readable difference report (what differs, where and by how much).
std::string format_comparison(const ReplayComparison& c);

}  // namespace amb::host::replay
