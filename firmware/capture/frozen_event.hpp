#pragma once
// A frozen capture window: what the loop hands to the non-real-time event writer. The sample
// storage is allocated once at configure; the loop fills it without allocating.
#include <cstdint>
#include <vector>

#include "firmware/app/loop_sample.hpp"
#include "firmware/capture/trigger_cause.hpp"

namespace amb::fw {

/// What the loop knows about the window when it freezes it (the static metadata — board,
/// gains, calibration — is added by the writer from the board configuration).
struct FrozenEventHeader {
  uint64_t capture_number = 0;    ///< frozen windows since configure, from 1
  TriggerCause cause = TriggerCause::none;  ///< primary cause (see primary_cause)
  uint32_t cause_mask = 0;        ///< every cause that asserted on the trigger sample (cause_bit)
  uint8_t cutoff_channels = 0;    ///< channels (bit i: axis i) cut off at the trigger
  uint32_t trigger_index = 0;     ///< index of the trigger sample in the window (= pre-trigger samples held)
  uint32_t sample_count = 0;      ///< valid samples in the window
  uint64_t trigger_seq = 0;       ///< LoopSample::seq of the trigger sample
  int64_t trigger_t_ns = 0;       ///< HAL clock time of the trigger sample, ns
  float speed_at_trigger_hz = 0.0f;  ///< speed estimate at the trigger sample, Hz
  int64_t first_t_ns = 0;         ///< time of the first sample in the window, ns
  int64_t last_t_ns = 0;          ///< time of the last sample in the window, ns
  uint32_t seq_gaps = 0;          ///< discontinuities of seq inside the window (0: none lost)
  uint64_t events_lost_before = 0;///< triggers lost for want of a free buffer since configure
};

struct FrozenEvent {
  FrozenEventHeader header;
  std::vector<LoopSample> samples;  ///< capacity pre + post; the first header.sample_count are valid
};

}  // namespace amb::fw
