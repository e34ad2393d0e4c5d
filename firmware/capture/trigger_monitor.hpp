#pragma once
// Phase A trigger conditions, evaluated on every loop sample (real-time: no allocation,
// locks, system calls or exceptions after configure).
//
// Level conditions (orbit radius, current/saturation, channel cut-off, external input) have
// a debounce (the raw condition must hold for N consecutive samples to assert) and, where it
// makes sense, a hysteresis (an asserted condition clears only below limit - hysteresis).
// The orbit, current and cut-off conditions are only evaluated while the rotor is meant to
// be centred with the amplifiers on (settling .. spinning_down); otherwise they are clear.
// Edge conditions (AMB switch-off, landing command, manual request) assert for one sample.
#include <array>
#include <cstdint>

#include "firmware/app/loop_sample.hpp"
#include "firmware/capture/capture_params.hpp"
#include "firmware/capture/trigger_cause.hpp"
#include "firmware/control/axis_transform.hpp"

namespace amb::fw {

class TriggerMonitor {
 public:
  /// `sensor_angle_deg`: directions of the sensors [A1, A2, B1, B2] from the upward vertical,
  /// deg (the board's rig.sensor angles). `rate_hz`: loop rate, to turn times into samples.
  void configure(const TriggerParams& p, const std::array<double, 4>& sensor_angle_deg, double rate_hz);

  /// [RT] Evaluate one sample. `manual_request`: a manual trigger was requested since the
  /// last sample. Returns the causes that became asserted on this sample (cause_bit mask).
  uint32_t update(const LoopSample& s, bool manual_request);

  /// Causes whose level condition is asserted now (edge causes never appear here).
  uint32_t asserted() const { return asserted_; }
  /// True when no level condition is asserted or pending (raw condition true, debouncing).
  bool all_clear() const { return asserted_ == 0 && !pending_; }
  /// Channels (bit i: axis i) whose cut-off condition is asserted now.
  uint8_t cutoff_channels() const { return cutoff_mask_; }
  /// Largest orbit radius over the sensor planes on the last sample, m.
  double last_orbit_radius_m() const { return last_radius_m_; }

 private:
  /// Debounced level with hysteresis: `over` counts towards assertion, `clear` releases.
  struct Level {
    uint32_t debounce_n = 1;
    uint32_t count = 0;
    bool on = false;
    /// Returns true on the sample it asserts.
    bool update(bool over, bool clear);
    void reset() { count = 0; on = false; }
  };

  TriggerParams p_{};
  std::array<AxisTransform, 2> xf_{};
  Level orbit_{}, current_{}, external_{};
  std::array<Level, 4> cutoff_{};
  uint32_t asserted_ = 0;
  bool pending_ = false;
  uint8_t cutoff_mask_ = 0;
  double last_radius_m_ = 0.0;
  bool have_prev_ = false;
  uint32_t prev_flags_ = 0;
  uint8_t prev_phase_ = 0;
};

}  // namespace amb::fw
