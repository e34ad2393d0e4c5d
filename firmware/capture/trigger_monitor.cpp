#include "firmware/capture/trigger_monitor.hpp"

#include <algorithm>
#include <cmath>

#include "firmware/app/supervisor.hpp"

namespace amb::fw {
namespace {

uint32_t samples_for(double t_s, double rate_hz) {
  // At least one sample: a debounce of 0 asserts on the first sample that exceeds.
  return static_cast<uint32_t>(std::max(1.0, std::ceil(t_s * rate_hz - 1e-9)));
}

bool centred_phase(uint8_t phase) {
  const auto p = static_cast<Phase>(phase);
  return p == Phase::settling || p == Phase::levitated || p == Phase::spinning_up ||
         p == Phase::at_speed || p == Phase::spinning_down;
}

bool landing_phase(uint8_t phase) {
  const auto p = static_cast<Phase>(phase);
  return p == Phase::spinning_down || p == Phase::lowering;
}

}  // namespace

bool TriggerMonitor::Level::update(bool over, bool clear) {
  if (on) {
    if (clear) reset();
    return false;
  }
  count = over ? count + 1 : 0;
  if (count >= debounce_n) {
    on = true;
    return true;
  }
  return false;
}

void TriggerMonitor::configure(const TriggerParams& p, const std::array<double, 4>& sensor_angle_deg,
                               double rate_hz) {
  p_ = p;
  for (size_t b = 0; b < 2; ++b)
    // The actuator angles are not used here (only sensors_to_xy); pass the sensor pair.
    xf_[b].configure({sensor_angle_deg[2 * b], sensor_angle_deg[2 * b + 1]},
                     {sensor_angle_deg[2 * b], sensor_angle_deg[2 * b + 1]});
  orbit_ = {};
  current_ = {};
  external_ = {};
  orbit_.debounce_n = samples_for(p.orbit.debounce_s, rate_hz);
  current_.debounce_n = samples_for(p.current.debounce_s, rate_hz);
  external_.debounce_n = samples_for(p.external.debounce_s, rate_hz);
  for (auto& c : cutoff_) c = Level{samples_for(p.cutoff.debounce_s, rate_hz), 0, false};
  asserted_ = 0;
  pending_ = false;
  cutoff_mask_ = 0;
  last_radius_m_ = 0.0;
  have_prev_ = false;
  prev_flags_ = 0;
  prev_phase_ = 0;
}

uint32_t TriggerMonitor::update(const LoopSample& s, bool manual_request) {
  uint32_t rising = 0;
  const bool supervised = (s.flags & flag_amplifiers_enabled) && centred_phase(s.phase);

  // Orbit radius at each sensor plane from the two inclined sensors.
  double radius = 0.0;
  for (size_t b = 0; b < 2; ++b) {
    const auto xy = xf_[b].sensors_to_xy({s.displacement_m[2 * b], s.displacement_m[2 * b + 1]});
    radius = std::max(radius, std::hypot(xy[0], xy[1]));
  }
  last_radius_m_ = radius;

  double i_max = 0.0;
  for (float i : s.coil_current_a) i_max = std::max(i_max, static_cast<double>(std::abs(i)));
  const bool saturated = (s.flags & flag_saturated) != 0;

  pending_ = false;
  if (p_.orbit.enabled && supervised) {
    const bool over = radius > p_.orbit.limit_m;
    if (orbit_.update(over, radius < p_.orbit.limit_m - p_.orbit.hysteresis_m)) rising |= cause_bit(TriggerCause::orbit_radius);
    pending_ = pending_ || over;
  } else {
    orbit_.reset();
  }

  if (p_.current.enabled && supervised) {
    const bool sat = p_.current.on_saturation && saturated;
    const bool over = i_max > p_.current.limit_a || sat;
    const bool clear = i_max < p_.current.limit_a - p_.current.hysteresis_a && !sat;
    if (current_.update(over, clear))
      rising |= cause_bit(i_max > p_.current.limit_a ? TriggerCause::current_limit : TriggerCause::saturation);
    pending_ = pending_ || over;
  } else {
    current_.reset();
  }

  cutoff_mask_ = 0;
  for (size_t k = 0; k < 4; ++k) {
    Level& c = cutoff_[k];
    if (p_.cutoff.enabled && supervised) {
      const bool over = std::abs(s.coil_current_a[k]) < p_.cutoff.near_zero_a &&
                        std::abs(s.current_demand_a[k]) > p_.cutoff.min_demand_a;
      if (c.update(over, !over)) rising |= cause_bit(TriggerCause::channel_cutoff);
      pending_ = pending_ || over;
    } else {
      c.reset();
    }
    if (c.on) cutoff_mask_ = static_cast<uint8_t>(cutoff_mask_ | (1u << k));
  }

  if (p_.external.enabled) {
    const bool high = (s.flags & flag_external_trigger) != 0;
    if (external_.update(high, !high)) rising |= cause_bit(TriggerCause::external_input);
    pending_ = pending_ || high;
  } else {
    external_.reset();
  }

  if (have_prev_) {
    if (p_.switch_off.enabled && (prev_flags_ & flag_amplifiers_enabled) && !(s.flags & flag_amplifiers_enabled))
      rising |= cause_bit(TriggerCause::amb_switch_off);
    const bool landing_input_rise = (s.flags & flag_landing_request) && !(prev_flags_ & flag_landing_request);
    const bool landing_phase_entry = landing_phase(s.phase) && !landing_phase(prev_phase_) &&
                                     (s.flags & flag_amplifiers_enabled);
    if (p_.landing.enabled && (landing_input_rise || landing_phase_entry))
      rising |= cause_bit(TriggerCause::landing_command);
  }
  if (p_.manual.enabled && manual_request) rising |= cause_bit(TriggerCause::manual);
  have_prev_ = true;
  prev_flags_ = s.flags;
  prev_phase_ = s.phase;

  asserted_ = (orbit_.on ? cause_bit(TriggerCause::orbit_radius) : 0u) |
              (current_.on ? cause_bit(TriggerCause::current_limit) : 0u) |
              (cutoff_mask_ ? cause_bit(TriggerCause::channel_cutoff) : 0u) |
              (external_.on ? cause_bit(TriggerCause::external_input) : 0u);
  return rising;
}

}  // namespace amb::fw
