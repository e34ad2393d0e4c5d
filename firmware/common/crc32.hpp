#pragma once
// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320), table-free bitwise variant: small,
// bounded time per byte, no static tables to initialise. Used for events and wear records.
#include <cstddef>
#include <cstdint>
#include <span>

namespace amb::fw {

/// Continue a CRC-32 over `data` from a previous value `crc` (start with 0).
inline uint32_t crc32(std::span<const uint8_t> data, uint32_t crc = 0) {
  crc = ~crc;
  for (uint8_t b : data) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

}  // namespace amb::fw
