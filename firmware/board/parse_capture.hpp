#pragma once
// Parser of the board file's optional [capture] and [triggers] tables (see
// firmware/capture/capture_params.hpp for the meaning and units of every key).
#include "firmware/board/toml_reader.hpp"
#include "firmware/capture/capture_params.hpp"

namespace amb::board {

/// Read [capture] into `c` (keys absent: defaults). `rate_hz`: the loop rate, to bound the
/// ring and event-buffer memory. Throws BoardError naming the key on a bad or unknown key.
void parse_capture(TableReader r, fw::CaptureParams& c, double rate_hz);

/// Read [triggers] (sub-tables orbit, current, cutoff, switch_off, landing, external, manual)
/// into `t`. Debounce times are rounded up to whole loop periods by the capture.
void parse_triggers(TableReader r, fw::TriggerParams& t);

}  // namespace amb::board
