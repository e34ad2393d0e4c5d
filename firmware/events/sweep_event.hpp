#pragma once
// The board's loop-sensitivity sweep (ISO 14839-3) as stored: an AMBE version-4 file of record
// kind `sweep` (docs/event-format.md "Sweep events"), in the same store, with the same CRC-32,
// download and retention as drop events. The metadata block is the drop event's (board, rig,
// calibration, controller in force); the sweep section holds the plan and, per completed axis,
// the excitation e, the controller output u_c, the summing point u = u_c + e and the axis'
// position reading y at the loop rate. Non-real-time.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "firmware/events/event_record.hpp"
#include "firmware/sweep/sweep_generator.hpp"

namespace amb::board { struct BoardConfig; }

namespace amb::fw {

inline constexpr uint16_t k_sweep_event_format_version = 4;
inline constexpr size_t k_sweep_header_bytes = 96;
inline constexpr size_t k_sweep_axis_header_bytes = 8;

struct SweepAxisData {
  uint8_t axis = 0;                 ///< control axis 0..3 [A1, A2, B1, B2]
  std::vector<float> excitation_a;  ///< e, A
  std::vector<float> controller_output_a;  ///< u_c, A
  std::vector<float> summing_point_a;      ///< u = u_c + e, A
  std::vector<float> sensor_m;      ///< y: position along this actuator axis (controller frame), m
};

struct SweepEvent {
  EventMetadata meta;               ///< as a drop event's (cause none; first/last_t_ns span the sweep)
  uint8_t injection = 0;            ///< 0 controller output (the one implemented), 1 sensor (reserved)
  uint8_t excitation = 0;           ///< 0 multisine, 1 stepped sine (reserved)
  bool aborted = false;
  SweepAbort abort_reason = SweepAbort::none;
  uint32_t samples_per_period = 0;  ///< N
  uint32_t settle_periods = 0;
  uint32_t recorded_periods = 0;    ///< P
  double speed_hz = 0.0;            ///< speed (drive command) at the start, Hz
  double bias_current_a = 0.0;      ///< the amplitude's reference, A
  double loop_delay_periods = 0.0;  ///< board's declared loop delay, periods
  double amplitude_a = 0.0;         ///< peak of e, A
  double crest_factor = 0.0;        ///< peak / rms of one period of e
  double abort_orbit_m = 0.0;       ///< orbit radius that aborts, m
  double amplitude_limit_a = 0.0;   ///< board limit of the amplitude, A
  int64_t start_t_ns = 0;           ///< HAL time of the first recorded sample, ns
  uint64_t start_seq = 0;           ///< its loop period counter
  std::vector<uint32_t> bins;       ///< excited bins; line frequency = bin * rate_hz / N
  std::vector<SweepAxisData> axes;  ///< completed axes in the order swept, each P * N samples
  uint16_t format_version = 0;      ///< set by decode_sweep_event
};

/// Bytes of a sweep event file: preamble, metadata, sweep header, lines, axes, CRC.
constexpr uint64_t sweep_event_file_bytes(uint64_t lines, uint64_t axes, uint64_t samples_per_axis) {
  return 32 + 616 + k_sweep_header_bytes + 4 * lines + axes * (k_sweep_axis_header_bytes + 16 * samples_per_axis) + 4;
}

/// The record of a finished sweep (the generator's view), with the board's metadata.
SweepEvent make_sweep_event(const SweepCaptureView& v, const board::BoardConfig& board, uint64_t event_number);

std::vector<uint8_t> encode_sweep_event(const SweepEvent& e);
/// Decode a sweep event. Returns false with `error` naming what is wrong ("truncated: ...",
/// "bad checksum: ...", "not a sweep event: ...", "inconsistent sizes: ...", "bad sweep
/// header: ..."); `out` is only written on success.
bool decode_sweep_event(std::span<const uint8_t> bytes, SweepEvent& out, std::string& error);

}  // namespace amb::fw
