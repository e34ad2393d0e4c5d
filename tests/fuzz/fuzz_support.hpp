#pragma once
// Helpers shared by the fuzz targets: the formats carry checksums that a mutating fuzzer
// almost never satisfies, so the targets also try each input with its checksums repaired,
// which lets the fuzzer reach the field validation behind them.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "firmware/common/crc32.hpp"
#include "firmware/persistence/crc32c.hpp"

namespace amb::fuzz {

inline void put_le32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}

/// AMBE / AMBW: CRC-32 of everything before the last 4 bytes, stored there little-endian.
inline std::vector<uint8_t> with_trailing_crc32(std::span<const uint8_t> in) {
  std::vector<uint8_t> out(in.begin(), in.end());
  if (out.size() >= 8) put_le32(out.data() + out.size() - 4, fw::crc32(std::span<const uint8_t>(out.data(), out.size() - 4)));
  return out;
}

/// Generation-store container: 28-byte header (magic, version, reserved, generation, payload
/// size, payload CRC-32C, header CRC-32C); size and both checksums made consistent.
inline std::vector<uint8_t> with_container_checksums(std::span<const uint8_t> in) {
  constexpr size_t k_header = 28;
  std::vector<uint8_t> out(in.begin(), in.end());
  if (out.size() < k_header) return out;
  const std::span<const uint8_t> payload(out.data() + k_header, out.size() - k_header);
  put_le32(out.data() + 16, static_cast<uint32_t>(payload.size()));
  put_le32(out.data() + 20, fw::crc32c(payload));
  put_le32(out.data() + 24, fw::crc32c(std::span<const uint8_t>(out.data(), k_header - 4)));
  return out;
}

}  // namespace amb::fuzz
