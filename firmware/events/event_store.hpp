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
// Protection (e.g. "not yet downloaded by the host") is held in memory, not persisted.
// Files are written with Storage::write_atomic, so a file is either complete or absent.
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
  uint64_t write_errors = 0;     ///< write_atomic failures
};

class EventStore {
 public:
  /// Scans `storage` for existing event files (reads each once to learn its size).
  EventStore(hal::Storage& storage, const CaptureParams& params);

  /// Number the next stored event will get.
  uint64_t next_number() const { return next_; }
  /// Store `bytes` as event `number` (normally next_number()). Applies the policy. Returns
  /// false with `error` set if refused or the write failed; counters say which.
  bool store(uint64_t number, std::span<const uint8_t> bytes, std::string& error);
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
  StoreCounters counters_{};
};

}  // namespace amb::fw
