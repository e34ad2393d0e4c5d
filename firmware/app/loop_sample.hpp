#pragma once
// The fixed-size record of one loop period: what the capture ring stores and replays.
#include <array>
#include <cstdint>

namespace amb::fw {

/// Bits of LoopSample::flags.
enum SampleFlags : uint32_t {
  flag_amplifiers_enabled = 1u << 0,
  flag_saturated = 1u << 1,
  flag_read_failed = 1u << 2,
  flag_levitated = 1u << 3,
  flag_fault = 1u << 4,
  flag_landing_request = 1u << 5,
  flag_external_trigger = 1u << 6,
  flag_amplifier_fault = 1u << 7,
};

struct LoopSample {
  uint64_t seq = 0;                           ///< loop period counter since configure (gap = lost sample)
  int64_t t_ns = 0;                           ///< HAL clock time of the input sample, ns
  std::array<float, 4> displacement_m{};      ///< sensor readings [A1, A2, B1, B2], m
  std::array<float, 4> coil_current_a{};      ///< measured control currents per actuator axis, A
  std::array<float, 4> current_demand_a{};    ///< demands written this period, A
  float speed_hz = 0.0f;                      ///< speed estimate (tach, tracker, else command), Hz
  float speed_command_hz = 0.0f;              ///< drive set-point, Hz
  uint8_t state = 0;                          ///< fw::State
  uint8_t phase = 0;                          ///< fw::Phase
  uint8_t fault = 0;                          ///< fw::FaultReason
  uint8_t reserved = 0;
  uint32_t flags = 0;                         ///< SampleFlags
};

}  // namespace amb::fw
