#pragma once
// Synthetic loop samples whose every field is a function of seq, so a test can tell a torn or
// misplaced sample from a good one.
#include <cmath>
#include <cstdint>

#include "firmware/app/loop_sample.hpp"
#include "firmware/app/supervisor.hpp"

namespace amb::test {

/// A healthy levitated sample at 10 kHz (unless `rate_hz` given), with `extra_flags`.
inline fw::LoopSample synthetic_sample(uint64_t seq, uint32_t extra_flags = 0, double rate_hz = 10000.0) {
  fw::LoopSample s;
  s.seq = seq;
  s.t_ns = static_cast<int64_t>(std::llround(static_cast<double>(seq) * 1e9 / rate_hz));
  // Small, seq-dependent values well inside every trigger limit.
  for (size_t i = 0; i < 4; ++i) {
    const auto k = static_cast<uint32_t>((seq * 2654435761u + i * 40503u) & 0xFFFFu);
    s.displacement_m[i] = static_cast<float>(static_cast<double>(k) * 1e-10);   // < 6.6 um
    s.coil_current_a[i] = 0.5f + static_cast<float>(k) * 1e-6f;                // 0.5 .. 0.57 A
    s.current_demand_a[i] = s.coil_current_a[i];
  }
  s.speed_hz = static_cast<float>(seq % 1000);
  s.speed_command_hz = 45.0f;
  s.state = static_cast<uint8_t>(fw::State::running);
  s.phase = static_cast<uint8_t>(fw::Phase::at_speed);
  s.fault = 0;
  s.speed_quality = static_cast<uint8_t>(seq & 0xFF);
  s.flags = fw::flag_amplifiers_enabled | fw::flag_levitated | extra_flags;
  return s;
}

/// True if `s` is exactly synthetic_sample(s.seq, flags-without-extras).
inline bool is_intact(const fw::LoopSample& s) {
  const fw::LoopSample r = synthetic_sample(s.seq, s.flags & ~(fw::flag_amplifiers_enabled | fw::flag_levitated));
  return s.t_ns == r.t_ns && s.displacement_m == r.displacement_m && s.coil_current_a == r.coil_current_a &&
         s.current_demand_a == r.current_demand_a && s.speed_hz == r.speed_hz &&
         s.speed_command_hz == r.speed_command_hz && s.state == r.state && s.phase == r.phase &&
         s.speed_quality == r.speed_quality && (s.flags & r.flags) == r.flags &&
         (s.tach_hz == r.tach_hz || (std::isnan(s.tach_hz) && std::isnan(r.tach_hz)));
}

}  // namespace amb::test
