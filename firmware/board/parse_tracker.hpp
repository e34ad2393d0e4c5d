#pragma once
#include "firmware/board/toml_reader.hpp"
#include "firmware/tracking/tracker_params.hpp"

namespace amb::board {
/// [tracker]: enabled, channel, window ("hamming" | "hann"), window_s, overlap, nfft,
/// min_speed_hz, max_speed_hz, search_half_band_hz, max_accel_hz_per_s, orders (array),
/// speed_source ("tach" | "tracker" | "command"), tach_disagreement_fraction, stale_after_s,
/// poll_period_s, status_frame_period_s.
void parse_tracker(TableReader r, fw::TrackerParams& t, double rate_hz);
}  // namespace amb::board
