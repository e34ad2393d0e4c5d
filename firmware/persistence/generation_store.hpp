#pragma once
// Power-loss-safe storage of one record in two generations (A/B) on top of hal::Storage.
// Each slot holds a container: header (magic "AMBG", version, generation number, payload size,
// payload CRC-32C, header CRC-32C (see crc32c.hpp for why not CRC-32)) followed by the payload. A new record always goes to the slot
// that does NOT hold the newest valid generation, so a write torn at any byte (even on a
// storage whose write_atomic is not atomic) leaves the newest good record untouched. At open
// the valid slot with the highest generation wins; torn or corrupt slots are reported.
// Not real-time: called from the supervisory / storage thread.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hal/interfaces.hpp"

namespace amb::fw {

/// Bytes of a slot's container header (magic, version, generation, payload size, payload
/// CRC-32C, header CRC-32C, reserved) in front of the payload.
inline constexpr size_t k_generation_header_bytes = 4 + 2 + 2 + 8 + 4 + 4 + 4;

/// What open() found.
struct GenerationReport {
  bool found = false;          ///< a valid generation exists
  uint64_t generation = 0;     ///< the newest valid generation (0: none)
  int slot = -1;               ///< 0: A, 1: B, -1: none
  int corrupt_slots = 0;       ///< slots present but torn or corrupt (0..2)
  std::string detail;          ///< human-readable notes about each slot
};

class GenerationStore {
 public:
  /// Slots are stored as `<base_name>.a` and `<base_name>.b` in `storage` (which must outlive this).
  GenerationStore(hal::Storage& storage, std::string base_name);

  /// Scan both slots and load the newest valid payload into `payload` (empty if none).
  GenerationReport open(std::vector<uint8_t>& payload);
  /// Store `payload` as generation newest+1 in the other slot. On failure the previous
  /// generation stays the newest; returns false with `error` set.
  bool store(std::span<const uint8_t> payload, std::string& error);

  uint64_t generation() const { return generation_; }
  const std::string& slot_name(int slot) const { return names_[static_cast<size_t>(slot)]; }

  /// Container encoding (exposed for tests).
  static std::vector<uint8_t> encode(uint64_t generation, std::span<const uint8_t> payload);
  /// Validate a container; on success fills `generation` and `payload`.
  static bool decode(const std::vector<uint8_t>& bytes, uint64_t& generation, std::vector<uint8_t>& payload,
                     std::string& error);

 private:
  hal::Storage& storage_;
  std::string names_[2];
  uint64_t generation_ = 0;
  int newest_slot_ = -1;
};

}  // namespace amb::fw
