#pragma once
// Why the floating capture froze a window (Phase A). Values are stored in event files: append
// only, never renumber.
#include <cstdint>

namespace amb::fw {

enum class TriggerCause : uint8_t {
  none = 0,
  orbit_radius = 1,     ///< orbit radius over the limit at a sensor plane
  current_limit = 2,    ///< |control current| over the limit
  saturation = 3,       ///< controller output saturated (flag_saturated)
  channel_cutoff = 4,   ///< measured current ~0 while the demand is not
  amb_switch_off = 5,   ///< amplifiers enabled -> disabled
  landing_command = 6,  ///< landing commanded (phase or landing input)
  external_input = 7,   ///< external discrete trigger input
  manual = 8,           ///< manual request from the supervisory link
};
inline constexpr int k_trigger_causes = 9;

/// Bit of a cause in a cause mask.
constexpr uint32_t cause_bit(TriggerCause c) { return 1u << static_cast<uint32_t>(c); }

/// Stable lower-case name ("orbit_radius", ...); "unknown" for values not listed.
inline const char* to_string(TriggerCause c) {
  switch (c) {
    case TriggerCause::none: return "none";
    case TriggerCause::orbit_radius: return "orbit_radius";
    case TriggerCause::current_limit: return "current_limit";
    case TriggerCause::saturation: return "saturation";
    case TriggerCause::channel_cutoff: return "channel_cutoff";
    case TriggerCause::amb_switch_off: return "amb_switch_off";
    case TriggerCause::landing_command: return "landing_command";
    case TriggerCause::external_input: return "external_input";
    case TriggerCause::manual: return "manual";
  }
  return "unknown";
}

/// The cause reported when several assert on the same sample: the most specific first.
inline TriggerCause primary_cause(uint32_t mask) {
  constexpr TriggerCause order[] = {TriggerCause::channel_cutoff, TriggerCause::current_limit,
                                    TriggerCause::saturation,     TriggerCause::orbit_radius,
                                    TriggerCause::amb_switch_off, TriggerCause::landing_command,
                                    TriggerCause::external_input, TriggerCause::manual};
  for (TriggerCause c : order)
    if (mask & cause_bit(c)) return c;
  return TriggerCause::none;
}

}  // namespace amb::fw
