#pragma once
// The board's binary event file, `AMBE` version 3 (little-endian, CRC-32): layout in
// docs/event-format.md. Version 2 added the board-analysis section (speed source and quality,
// quick-look aux-bearing load); version 3 adds the tachometer channel to every sample (84-byte
// samples: the rotor speed during a drop whatever the board's speed source). Versions 1 and 2
// are still read (no analysis section in v1; no tachometer channel: tach_hz -1, "none").
// Non-real-time.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "firmware/events/event_record.hpp"

namespace amb::fw {

inline constexpr uint16_t k_event_format_version = 3;      ///< written (drop events)
inline constexpr uint16_t k_event_format_oldest_read = 1;  ///< oldest version read
/// Version 4 (issue 35) gives the u16 at offset 6 (reserved, 0, in versions 1..3) a meaning:
/// the record kind. A drop event is still written as version 3 (byte-identical); a version-4
/// file of kind `drop` has the version-3 layout. Sweep events: firmware/events/sweep_event.hpp.
inline constexpr uint16_t k_event_format_newest_read = 4;
enum class EventKind : uint16_t { drop = 0, sweep = 1 };
const char* to_string(EventKind k);
inline constexpr size_t k_event_preamble_bytes = 32;
inline constexpr size_t k_event_meta_bytes_v1 = 616;
inline constexpr size_t k_event_sample_bytes_v1 = 80;      ///< versions 1 and 2
inline constexpr size_t k_event_sample_bytes_v3 = 84;      ///< + f32 tach_hz
inline constexpr size_t k_event_diagnosis_bytes_v1 = 392;
inline constexpr size_t k_event_analysis_bytes_v2 = 120;

/// Bytes of a version-3 event file of `samples` samples, with or without the diagnosis
/// section (the analysis section is always written): preamble, metadata, samples,
/// diagnosis, analysis, CRC.
constexpr uint64_t event_file_bytes(uint64_t samples, bool with_diagnosis) {
  return k_event_preamble_bytes + k_event_meta_bytes_v1 + samples * k_event_sample_bytes_v3 +
         (with_diagnosis ? k_event_diagnosis_bytes_v1 : 0) + k_event_analysis_bytes_v2 + 4;
}

/// Encode `r` (with its diagnosis if has_diagnosis) into a complete version-3 file image
/// (the analysis section is always written; zeros when has_analysis is false).
std::vector<uint8_t> encode_event(const EventRecord& r);
/// Encode as version 1 (no analysis section, no tachometer): for tests of the old-file reader.
std::vector<uint8_t> encode_event_v1(const EventRecord& r);
/// Encode as version 2 (no tachometer channel): for tests of the old-file reader.
std::vector<uint8_t> encode_event_v2(const EventRecord& r);

/// The record kind of a file image: versions 1..3 are drop events; version 4 says. Returns
/// false (and `error`) when the bytes are not an AMBE preamble of a known version. Reads the
/// preamble only (no checksum check: decode_event / decode_sweep_event do that).
bool peek_event_kind(std::span<const uint8_t> bytes, EventKind& kind, uint16_t& version, std::string& error);

/// The frame every AMBE file shares, after its preamble was read: the file holds exactly the
/// `declared_bytes` of its header (shorter: "truncated", longer: "inconsistent sizes"), at least
/// a preamble and a checksum, and its trailing CRC-32 matches. False with `error` otherwise.
bool check_event_frame(std::span<const uint8_t> bytes, uint64_t declared_bytes, std::string& error);

/// Decode a file image of a drop event. A sweep event is refused ("not a drop event: ..."). Returns false with `error` saying what is wrong: "truncated: ...",
/// "bad checksum: ...", "unsupported version ...", "not an AMBE event file: ...",
/// "inconsistent sizes: ...". `out` is only written on success.
bool decode_event(std::span<const uint8_t> bytes, EventRecord& out, std::string& error);


}  // namespace amb::fw
