#pragma once
// A SIL drop with the firmware's floating capture attached (test support): lift off, spin
// up, hold, cut every AMB channel in the plant (the firmware is not told), let the firmware
// trigger, enter the safe state and record the post-trigger window; the event writer runs
// Phase B, encodes AMBE v1 and stores the file. Returned: the stored file images.
//
// The front end hands the firmware float32-exact samples (Float32FrontEnd), as a real ADC
// front end does (16-bit counts times a power-of-two scale are exact in float32): the
// capture stores float32, and only what the firmware saw can be replayed bit for bit.
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"

namespace amb::test {

struct CaptureRunOptions {
  double hold_s = 0.3;              ///< time at speed before the cut, s
  double post_trigger_s = 0.6;      ///< post-trigger window of both captures, s
  double full_pre_trigger_s = 8.0;  ///< pre-trigger window of the "full history" capture (reaches back to configure), s
  /// The board takes its speed from the tracker (tracker.speed_source "tracker") and a stand-in
  /// for the asynchronous tracker thread publishes every 50 loop periods: the rotor.s true
  /// speed + 0.1 %, confidence 0.87, lost (confidence 0.3) from 1.0 to 1.3 s after
  /// configure, nothing from 2.0 to 2.8 s (stale). Off: the board's tachometer source.
  bool tracker_speed_source = false;
};

struct CaptureRunResult {
  board::BoardConfig board;                 ///< the board as run (default capture window)
  std::vector<uint8_t> event_default;       ///< event of the board's own pre-trigger window (mid-run start)
  std::vector<uint8_t> event_full_history;  ///< event whose window starts at configure (seq 0)
  double cut_time_s = 0.0;
  std::string log;
};

/// Run it (about 4 s of simulated time). Throws std::runtime_error if a step fails.
CaptureRunResult run_sil_capture(const CaptureRunOptions& o = {});

/// Cached: the first call runs, later calls return the same result.
const CaptureRunResult& sil_capture();

}  // namespace amb::test
