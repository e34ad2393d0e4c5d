#pragma once
// Board-file settings of the on-board speed tracker ([tracker] table).
#include <cstddef>

#include "model/signal/speed_ridge_tracker.hpp"

namespace amb::fw {

struct TrackerParams {
  bool enabled = false;               ///< run the tracker on the board
  int channel = 0;                    ///< displacement channel fed to it, 0..3 [A1, A2, B1, B2]
  size_t max_gap_samples = 8;         ///< gaps bridged by holding the last value, samples
  model::signal::SpeedTrackerOptions options{};  ///< STFT and ridge settings (sample rate = loop rate)
};

}  // namespace amb::fw
