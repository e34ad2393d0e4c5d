#pragma once
// Board-file settings of the on-board speed tracker ([tracker] table) and of where the
// board's speed estimate comes from (speed_source).
#include <cstddef>
#include <cstdint>

#include "model/signal/speed_ridge_tracker.hpp"

namespace amb::fw {

/// Where LoopSample::speed_hz (capture stamp, event speed, Phase B orders) comes from.
enum class SpeedSource : uint8_t {
  tach = 0,     ///< the tachometer reading; without one, the drive command (the old behaviour)
  tracker = 1,  ///< the on-board STFT tracker; NaN with the lost flag when it has no fresh lock
  command = 2,  ///< the drive speed set-point
};
inline const char* to_string(SpeedSource s) {
  switch (s) {
    case SpeedSource::tach: return "tach";
    case SpeedSource::tracker: return "tracker";
    case SpeedSource::command: return "command";
  }
  return "?";
}

struct TrackerParams {
  bool enabled = false;               ///< run the tracker on the board
  int channel = 0;                    ///< displacement channel fed to it, 0..3 [A1, A2, B1, B2]
  size_t max_gap_samples = 8;         ///< gaps bridged by holding the last value, samples
  model::signal::SpeedTrackerOptions options{};  ///< STFT and ridge settings (sample rate = loop rate)
  SpeedSource speed_source = SpeedSource::tach;  ///< key speed_source: "tach" | "tracker" | "command"
  /// Tracker and tachometer disagree when |tracked - tach| > this fraction of the tach speed
  /// (both valid); each tracker update that disagrees is counted. Key tach_disagreement_fraction.
  double tach_disagreement_fraction = 0.02;
  /// A tracker update whose confidence is below this is published as lost (no speed), 0..1.
  /// A tracker left without its line (the speed beyond max_speed_hz, a channel without the
  /// shaft line) coasts on the strongest noise in its search band, which scores 0.15-0.3
  /// (the best of a few hundred noise bins over the chirp hypotheses); a real lock scores
  /// near 1. Key min_confidence.
  double min_confidence = 0.5;
  /// A tracked speed older than this (loop time since the tracker's last update) is treated as
  /// lost, never presented as fresh, s. Key stale_after_s.
  double stale_after_s = 0.5;
  /// Analysis thread: period between drains of the ring, s. Key poll_period_s.
  double poll_period_s = 0.02;
  /// Period of the CAN board-status frame (linux backend), s; key status_frame_period_s.
  double status_frame_period_s = 0.1;
};

}  // namespace amb::fw
