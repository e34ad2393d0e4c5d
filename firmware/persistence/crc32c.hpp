#pragma once
// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), bitwise. Used for the persistence
// container and the supervisory link's item and block checksums.
//
// Why not the CRC-32 (IEEE) of the record formats: an AMBW record (and any format that ends
// in its own little-endian CRC-32) has the same CRC-32 residue, whatever its content, so an
// IEEE CRC-32 over such an item cannot tell two valid records apart, and mixtures of two
// same-length valid records (torn in-place writes) pass it too. A different polynomial does
// not share that codeword structure.
#include <cstdint>
#include <span>

namespace amb::fw {

/// Continue a CRC-32C over `data` from a previous value `crc` (start with 0).
inline uint32_t crc32c(std::span<const uint8_t> data, uint32_t crc = 0) {
  crc = ~crc;
  for (uint8_t b : data) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0x82F63B78u & (0u - (crc & 1u)));
  }
  return ~crc;
}

}  // namespace amb::fw
