#pragma once
// Settings of the floating capture, its Phase A triggers and the event store, as the board
// file's [capture] and [triggers] tables give them (parser: firmware/board/parse_capture.cpp).
// Pure data with defaults: a board file without these tables gets exactly these values.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace amb::fw {

/// What the event store does when a new event does not fit (count or bytes).
enum class StoragePolicy : uint8_t {
  drop_oldest = 0,  ///< remove the oldest unprotected events until it fits; never the newest
  refuse_new = 1,   ///< keep what is stored, refuse (and count) the new event
};

/// Orbit radius at any sensor plane, from the two +-45 deg sensor readings.
struct OrbitTrigger {
  bool enabled = true;
  double limit_m = 0.2e-3;        ///< radius from the bearing centre that asserts, m
  double hysteresis_m = 0.02e-3;  ///< asserted until the radius falls below limit - hysteresis, m
  double debounce_s = 0.5e-3;     ///< the limit must be exceeded this long before it asserts, s
};

/// Control current over a limit, or the controller output saturated (flag_saturated).
struct CurrentTrigger {
  bool enabled = true;
  double limit_a = 2.0;           ///< |measured coil current| on any axis that asserts, A
  double hysteresis_a = 0.2;      ///< asserted until every |current| < limit - hysteresis, A
  bool on_saturation = true;      ///< flag_saturated asserts too
  double debounce_s = 1e-3;       ///< s
};

/// One or more channels cut off: measured current near zero while the demand is not.
struct CutoffTrigger {
  bool enabled = true;
  double near_zero_a = 0.05;      ///< |measured| below this counts as "no current", A
  double min_demand_a = 0.3;      ///< ... while |demand| is above this, A
  double debounce_s = 2e-3;       ///< for this long on the same channel, s
};

/// Edge triggers from the lifecycle: AMB switch-off (amplifiers enabled -> disabled) and a
/// landing command (phase enters spinning_down/lowering, or the landing input rises).
struct EdgeTrigger {
  bool enabled = true;
};

/// External discrete input (flag_external_trigger).
struct ExternalTrigger {
  bool enabled = true;
  double debounce_s = 1e-3;       ///< the input must be high this long, s
};

struct TriggerParams {
  OrbitTrigger orbit;
  CurrentTrigger current;
  CutoffTrigger cutoff;
  EdgeTrigger switch_off;
  EdgeTrigger landing;
  ExternalTrigger external;
  EdgeTrigger manual;             ///< manual request from the supervisory link
};

struct CaptureParams {
  double pre_trigger_s = 0.5;     ///< history kept before the trigger sample, s
  double post_trigger_s = 2.0;    ///< recorded from the trigger sample on, s
  int event_buffers = 2;          ///< frozen-event buffers pre-allocated (1..8); none free: event lost, counted
  double rearm_hold_s = 0.5;      ///< after a freeze, every condition must be clear this long to re-arm, s
  StoragePolicy storage_policy = StoragePolicy::drop_oldest;
  uint64_t storage_capacity_bytes = 256ull << 20;  ///< byte budget of stored event files
  int max_events = 64;            ///< stored event files at most
  double match_axial_tolerance_m = 0.01;    ///< importer: channel-to-rig match in axial position, m
  double match_angle_tolerance_deg = 5.0;   ///< importer: channel-to-rig match in direction, deg
  TriggerParams triggers;
};

/// Sample counts of a capture window at a loop rate (what FloatingCapture::configure allocates
/// from, what an event file holds, what the board file's storage budget is checked against).
struct CaptureSizes {
  uint32_t pre_samples = 0;   ///< pre-trigger samples: round(pre_trigger_s x rate)
  uint32_t post_samples = 1;  ///< post-trigger samples (trigger sample included), >= 1
  uint64_t ring_samples = 0;  ///< ring length: the power of two >= pre + post + 1
  uint32_t window_samples() const { return pre_samples + post_samples; }
};
/// `rate_hz`: loop rate, Hz.
inline CaptureSizes capture_sizes(const CaptureParams& p, double rate_hz) {
  CaptureSizes s;
  s.pre_samples = static_cast<uint32_t>(std::llround(p.pre_trigger_s * rate_hz));
  s.post_samples = std::max<uint32_t>(1, static_cast<uint32_t>(std::llround(p.post_trigger_s * rate_hz)));
  s.ring_samples = std::bit_ceil(static_cast<uint64_t>(s.pre_samples) + s.post_samples + 1);
  return s;
}

}  // namespace amb::fw
