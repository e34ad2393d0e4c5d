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

/// LoopSample::speed_quality bit 7: no valid speed this period (speed_hz is NaN).
inline constexpr uint8_t k_speed_lost_bit = 0x80;
/// Pack a speed confidence in [0, 1] and a lost flag into LoopSample::speed_quality.
constexpr uint8_t pack_speed_quality(double confidence, bool lost) {
  const double c = confidence > 1.0 ? 1.0 : (confidence > 0.0 ? confidence : 0.0);
  return static_cast<uint8_t>(static_cast<uint8_t>(c * 100.0 + 0.5) | (lost ? k_speed_lost_bit : 0u));
}

struct LoopSample;
/// Confidence of the sample's speed, 0..1.
inline double speed_confidence(const LoopSample& s);
/// True when the sample carries no valid speed.
inline bool speed_lost(const LoopSample& s);

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
  uint8_t speed_quality = 0;                  ///< bits 0..6: confidence of speed_hz, percent (0..100); bit 7: lost (speed_hz is NaN)
  uint32_t flags = 0;                         ///< SampleFlags
  /// The rig's tachometer (key-phasor) reading this period, Hz, whatever the board's speed
  /// source (speed_hz may be the tracker's): the rotor's spin-down during a drop. < 0: the rig
  /// has none; NaN: present but invalid. Stored from AMBE v3 on (older files read as -1).
  float tach_hz = -1.0f;
  /// Explicit padding to the 8-byte alignment, always 0, not stored: a sample has no
  /// indeterminate bytes (replay compares samples byte for byte).
  uint32_t reserved = 0;
};
static_assert(sizeof(LoopSample) == 88, "LoopSample: no implicit padding");

inline double speed_confidence(const LoopSample& s) { return static_cast<double>(s.speed_quality & 0x7Fu) / 100.0; }
inline bool speed_lost(const LoopSample& s) { return (s.speed_quality & k_speed_lost_bit) != 0; }

}  // namespace amb::fw
