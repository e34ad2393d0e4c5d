#pragma once
// The board's binary event file, `AMBE` version 2 (little-endian, CRC-32): layout in
// docs/event-format.md. Version 2 adds the board-analysis section (speed source and quality,
// quick-look aux-bearing load); version 1 files are still read (no analysis section).
// Non-real-time.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "firmware/events/event_record.hpp"

namespace amb::fw {

inline constexpr uint16_t k_event_format_version = 2;      ///< written
inline constexpr uint16_t k_event_format_oldest_read = 1;  ///< oldest version read
inline constexpr size_t k_event_preamble_bytes = 32;
inline constexpr size_t k_event_meta_bytes_v1 = 616;
inline constexpr size_t k_event_sample_bytes_v1 = 80;
inline constexpr size_t k_event_diagnosis_bytes_v1 = 392;
inline constexpr size_t k_event_analysis_bytes_v2 = 120;

/// Encode `r` (with its diagnosis if has_diagnosis) into a complete version-2 file image
/// (the analysis section is always written; zeros when has_analysis is false).
std::vector<uint8_t> encode_event(const EventRecord& r);
/// Encode as version 1 (no analysis section): for tests of the old-file reader.
std::vector<uint8_t> encode_event_v1(const EventRecord& r);

/// Decode a file image. Returns false with `error` saying what is wrong: "truncated: ...",
/// "bad checksum: ...", "unsupported version ...", "not an AMBE event file: ...",
/// "inconsistent sizes: ...". `out` is only written on success.
bool decode_event(std::span<const uint8_t> bytes, EventRecord& out, std::string& error);

/// Standard CRC-32 (same value as firmware/common/crc32.hpp), table-driven for the
/// megabyte-sized event files in the non-real-time writer and on the host.
uint32_t crc32_fast(std::span<const uint8_t> data, uint32_t crc = 0);

}  // namespace amb::fw
