#include "firmware/persistence/wear_store.hpp"

namespace amb::fw {

const char* to_string(WriteBackResult r) {
  switch (r) {
    case WriteBackResult::none: return "none";
    case WriteBackResult::accepted: return "accepted";
    case WriteBackResult::incomplete: return "incomplete";
    case WriteBackResult::checksum_mismatch: return "checksum_mismatch";
    case WriteBackResult::invalid_record: return "invalid_record";
    case WriteBackResult::wrong_board: return "wrong_board";
    case WriteBackResult::stale_sequence: return "stale_sequence";
    case WriteBackResult::refused_unsafe: return "refused_unsafe";
    case WriteBackResult::storage_failed: return "storage_failed";
    case WriteBackResult::aborted: return "aborted";
  }
  return "unknown";
}

WearStore::WearStore(hal::Storage& storage, std::string board_name)
    : gen_(storage, "wear"), board_name_(std::move(board_name)) {}

GenerationReport WearStore::open() {
  std::vector<uint8_t> payload;
  GenerationReport rep = gen_.open(payload);
  has_record_ = false;
  encoded_.clear();
  if (rep.found) {
    WearRecord r;
    std::string err;
    // The container CRC already holds; a payload that is not a record means a bug, not a tear.
    if (decode_wear_record(payload, r, err)) {
      record_ = r;
      encoded_ = std::move(payload);
      has_record_ = true;
    } else {
      rep.detail += "newest generation holds no valid wear record: " + err + "; ";
    }
  }
  return rep;
}

WriteBackResult WearStore::accept(const std::vector<uint8_t>& bytes, std::string& detail) {
  WearRecord r;
  if (!decode_wear_record(bytes, r, detail)) return WriteBackResult::invalid_record;
  if (r.board_name != board_name_) {
    detail = "record is for board '" + r.board_name + "', this is '" + board_name_ + "'";
    return WriteBackResult::wrong_board;
  }
  if (r.sequence != next_sequence()) {
    detail = "record sequence " + std::to_string(r.sequence) + ", expected " + std::to_string(next_sequence());
    return WriteBackResult::stale_sequence;
  }
  if (!gen_.store(bytes, detail)) return WriteBackResult::storage_failed;
  record_ = r;
  encoded_ = bytes;
  has_record_ = true;
  detail = "stored as generation " + std::to_string(gen_.generation());
  return WriteBackResult::accepted;
}

}  // namespace amb::fw
