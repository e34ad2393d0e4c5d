#pragma once
// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320), table-driven: one lookup per byte,
// bounded time per byte, the 1 KiB table built at compile time (nothing to initialise at run
// time). Used for events and wear records, on the board and on the host.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace amb::fw {

namespace crc32_detail {
constexpr std::array<uint32_t, 256> make_table() {
  std::array<uint32_t, 256> t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    t[i] = c;
  }
  return t;
}
inline constexpr std::array<uint32_t, 256> k_table = make_table();
}  // namespace crc32_detail

/// Continue a CRC-32 over `data` from a previous value `crc` (start with 0).
inline uint32_t crc32(std::span<const uint8_t> data, uint32_t crc = 0) {
  crc = ~crc;
  for (uint8_t b : data) crc = crc32_detail::k_table[(crc ^ b) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

}  // namespace amb::fw
