#include "host-tools/core/replay/replay_input.hpp"

namespace amb::host::replay {

std::vector<hal::replay::ReplaySample> replay_samples(std::span<const fw::LoopSample> recorded) {
  std::vector<hal::replay::ReplaySample> out(recorded.size());
  for (size_t k = 0; k < recorded.size(); ++k) {
    const fw::LoopSample& s = recorded[k];
    hal::replay::ReplaySample& r = out[k];
    r.analog.t_ns = s.t_ns;
    // float -> double is exact: the firmware sees the recorded values bit for bit.
    for (size_t i = 0; i < 4; ++i) {
      r.analog.displacement_m[i] = static_cast<double>(s.displacement_m[i]);
      r.analog.coil_current_a[i] = static_cast<double>(s.coil_current_a[i]);
    }
    r.analog.tach_speed_hz = static_cast<double>(s.tach_hz);  // -1 (no tachometer) in events before AMBE v3
    r.analog.fault_bits = 0;  // not recorded in LoopSample v1
    r.read_ok = (s.flags & fw::flag_read_failed) == 0;
    r.discrete.landing_request = (s.flags & fw::flag_landing_request) != 0;
    r.discrete.external_trigger = (s.flags & fw::flag_external_trigger) != 0;
    r.discrete.amplifier_fault = (s.flags & fw::flag_amplifier_fault) != 0;
  }
  return out;
}

TrackedUpdate tracked_update(const fw::LoopSample& recorded) {
  TrackedUpdate u;
  u.lost = (recorded.speed_quality & fw::k_speed_lost_bit) != 0;
  u.speed_hz = static_cast<double>(recorded.speed_hz);
  u.confidence = static_cast<double>(recorded.speed_quality & static_cast<uint8_t>(~fw::k_speed_lost_bit)) / 100.0;
  return u;
}

}  // namespace amb::host::replay
