#pragma once
// The board's wear record (AMBW v1, firmware/wear/wear_record.hpp), persisted power-loss
// safe in two generations (GenerationStore, items "wear.a"/"wear.b"). A record written back by
// the host replaces the stored one only after validation: format version, CRC, board name
// and sequence number (exactly one more than the stored one). Not real-time.
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/persistence/generation_store.hpp"
#include "firmware/wear/wear_record.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

/// Outcome of a write-back; the numeric values are served on the register map.
enum class WriteBackResult : uint16_t {
  none = 0,               ///< nothing committed yet
  accepted = 1,           ///< validated and persisted
  incomplete = 2,         ///< fewer bytes received than announced
  checksum_mismatch = 3,  ///< transfer CRC-32 does not match the announced one
  invalid_record = 4,     ///< not a valid AMBW record (magic, version, size, record CRC)
  wrong_board = 5,        ///< record belongs to another board
  stale_sequence = 6,     ///< sequence is not stored sequence + 1
  refused_unsafe = 7,     ///< refused: rotor levitating or running
  storage_failed = 8,     ///< could not be persisted (old record kept)
  aborted = 9,            ///< session aborted by the host
};
const char* to_string(WriteBackResult r);

class WearStore {
 public:
  /// `storage` must outlive this; `board_name` is the name records must carry.
  WearStore(hal::Storage& storage, std::string board_name);

  /// Load the newest valid generation. Returns the report (corrupt slots, generation).
  GenerationReport open();

  bool has_record() const { return has_record_; }
  const WearRecord& record() const { return record_; }
  /// The stored record's encoded bytes (empty if none).
  const std::vector<uint8_t>& encoded() const { return encoded_; }
  /// Sequence the next accepted record must carry.
  uint32_t next_sequence() const { return has_record_ ? record_.sequence + 1 : 1; }
  uint64_t generation() const { return gen_.generation(); }

  /// Validate `bytes` (an encoded AMBW record) and persist it. `detail` explains a refusal.
  WriteBackResult accept(const std::vector<uint8_t>& bytes, std::string& detail);

 private:
  GenerationStore gen_;
  std::string board_name_;
  bool has_record_ = false;
  WearRecord record_{};
  std::vector<uint8_t> encoded_;
};

}  // namespace amb::fw
