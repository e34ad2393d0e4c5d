#pragma once
// Event files on hal::Storage with a bounded footprint. Non-real-time.
//
// Names: "event_NNNNNNNN.ambe" (8-digit decimal event number, increasing; the store resumes
// after the highest number it finds). Limits: at most capture.max_events files and
// capture.storage_capacity_bytes bytes, and never more than the storage's free space.
// Policy when a new event does not fit:
//   drop_oldest — remove the oldest events that are not protected until it fits; the new
//                 event is never the one dropped. If it still does not fit: refused, counted.
//   refuse_new  — keep what is stored; the new event is refused and counted.
// The file system's free space is not part of the budget: when it is short, drop_oldest drops
// older events while that gives space back (never again until the storage has room, if a
// removal did not: something else is filling it); an event that still does not fit is a
// storage fault (`failed`, counted as no_space), which the EventWriter retries.
// Protection (e.g. "not yet downloaded by the host") is held in memory, not persisted.
// Files are written with Storage::write_atomic, so a file is either complete or absent.
// A refusal by the limits/policy is final; a failed write (I/O error, read-only or full
// file system at write time) is reported as `failed` so that the caller (EventWriter) can
// keep the event and retry.
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "firmware/capture/capture_params.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

struct StoreCounters {
  uint64_t written = 0;          ///< event files written
  uint64_t refused = 0;          ///< events not stored because of the limits/policy
  uint64_t dropped_oldest = 0;   ///< older events removed to make room
  uint64_t write_errors = 0;     ///< write_atomic failures (each attempt)
  uint64_t no_space = 0;         ///< attempts that found too little free space (each attempt)
  // Kept by the EventWriter (zero from EventStore::counters()):
  uint64_t retries = 0;          ///< write attempts of events that failed before
  uint64_t pending = 0;          ///< events waiting for a retry now (held in memory)
  uint64_t lost = 0;             ///< events given up: retry queue full, or still failing at stop()
};

/// Outcome of EventStore::put.
enum class StoreResult : uint8_t {
  stored = 0,   ///< on storage
  refused = 1,  ///< refused by the budget/policy (final)
  failed = 2,   ///< too little free space, or the write failed (storage fault); the caller may retry
};

class EventStore {
 public:
  /// Scans `storage` for existing event files (reads each once to learn its size).
  EventStore(hal::Storage& storage, const CaptureParams& params);

  /// Number the next stored event will get.
  uint64_t next_number() const { return next_; }
  /// Take the next number for an event that may be stored later (retries keep their number).
  uint64_t reserve_number() { return next_++; }
  /// Store `bytes` as event `number` (normally next_number()). Applies the policy. Returns
  /// what happened; `error` is set unless stored.
  StoreResult put(uint64_t number, std::span<const uint8_t> bytes, std::string& error);
  /// put() == stored.
  bool store(uint64_t number, std::span<const uint8_t> bytes, std::string& error) {
    return put(number, bytes, error) == StoreResult::stored;
  }
  /// Protect (or unprotect) an event from being dropped by drop_oldest.
  void set_protected(uint64_t number, bool is_protected);
  /// Stored event numbers, oldest first.
  std::vector<uint64_t> numbers() const;
  uint64_t bytes_used() const;
  const StoreCounters& counters() const { return counters_; }

  static std::string name_of(uint64_t number);
  /// Event number of a file name; false if it is not an event file name.
  static bool parse_name(const std::string& name, uint64_t& number);

 private:
  hal::Storage& storage_;
  CaptureParams p_;
  std::map<uint64_t, uint64_t> sizes_;  ///< number -> bytes
  std::set<uint64_t> protected_;
  uint64_t next_ = 1;
  bool drops_ineffective_ = false;  ///< a removal gave no space back: do not drop for free space
  StoreCounters counters_{};
};

}  // namespace amb::fw
