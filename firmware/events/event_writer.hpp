#pragma once
// The non-real-time event thread: takes frozen windows from the capture, runs Phase B and the
// bearing task's quick-look aux-bearing load on each, encodes it (AMBE v2) and stores it,
// then gives the buffer back to the loop.
// The loop never waits for it: if it falls behind, the capture loses (and counts) events.
//
// Storage faults: an event whose write fails (I/O error, read-only or full file system at
// write time, see EventStore) is kept in memory, in order, and retried with a backoff; new
// events queue behind it. The queue holds at most WriterOptions::max_pending events; when it
// is full the policy decides which one is given up (drop_oldest: the oldest waiting,
// refuse_new: the new one) and it is counted as lost. A refusal by the store's limits/policy
// is final and counted as refused, not retried.
#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "firmware/bearing/bearing_task.hpp"
#include "firmware/board/board.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/diagnosis/phase_b.hpp"
#include "firmware/events/event_record.hpp"
#include "firmware/events/event_store.hpp"
#include "firmware/events/sweep_event.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

struct WriterOptions {
  bool run_diagnosis = true;          ///< Phase B on every event
  diag::DiagnosisOptions diagnosis;   ///< its thresholds
  int idle_sleep_ms = 5;              ///< thread: sleep when nothing is waiting, ms
  int max_pending = 4;                ///< events held in memory for a retry after a failed write (>= 1)
  int retry_initial_ms = 50;          ///< first retry this long after a failed write, ms
  int retry_max_ms = 2000;            ///< backoff doubles up to this, ms
};

class EventWriter {
 public:
  /// `capture`, `storage` and `board` must outlive the writer.
  EventWriter(FloatingCapture& capture, hal::Storage& storage, const board::BoardConfig& board,
              WriterOptions options = {});
  ~EventWriter();

  /// Start / stop (and join) the writer thread. Stop processes what is already frozen.
  void start();
  void stop();
  /// Process every frozen event waiting now (the thread calls this; tests may call it
  /// directly instead of starting the thread). Returns the number processed.
  size_t poll();

  /// Called in the writer's thread after each event was processed (stored or not):
  /// the record (with diagnosis), its file name, whether it was stored now (false: refused,
  /// or waiting for a retry: store_counters().pending).
  std::function<void(const EventRecord&, const std::string& name, bool stored)> on_event;

  /// The loop's sweep generator (configure time; nullptr: none): a finished sweep is taken,
  /// encoded as a `sweep` event (AMBE v4) and stored like a drop event (same numbering, limits,
  /// policy and retries), then its buffer is handed back to the loop.
  void set_sweep_source(SweepGenerator* sweep) { sweep_ = sweep; }
  /// Called in the writer's thread after each sweep event was processed (like on_event).
  std::function<void(const SweepEvent&, const std::string& name, bool stored)> on_sweep;
  /// Sweep events written (stored now) and the number of the newest (0: none yet).
  uint64_t sweeps_stored() const { return sweeps_stored_.load(); }
  uint64_t last_sweep_number() const { return last_sweep_number_.load(); }

  /// The store's counters with the writer's retry counters (retries, pending, lost).
  StoreCounters store_counters() const;
  /// Last error message (refusal or write failure), empty if none.
  std::string last_error() const;
  EventStore& store() { return store_; }

 private:
  FloatingCapture& capture_;
  const board::BoardConfig& board_;
  WriterOptions o_;
  EventStore store_;
  BearingTask bearing_;   ///< quick-look load (configured from [bearing]; unconfigured without it)
  struct Pending {
    uint64_t number = 0;
    std::vector<uint8_t> bytes;
  };
  /// Try the waiting events in order (at most until one fails); returns how many left the queue.
  size_t flush_pending(std::chrono::steady_clock::time_point now);
  void enqueue(uint64_t number, std::vector<uint8_t> bytes);
  /// Store now (or queue behind the waiting events); what happened.
  StoreResult store_or_queue(uint64_t number, std::vector<uint8_t> bytes);
  SweepGenerator* sweep_ = nullptr;
  std::atomic<uint64_t> sweeps_stored_{0}, last_sweep_number_{0};
  mutable std::mutex m_;  ///< guards store_ counters, the retry counters and last_error_ for readers in other threads
  std::string last_error_;
  std::deque<Pending> pending_;   ///< writer thread only (counted under m_)
  std::chrono::steady_clock::time_point next_retry_{};
  int backoff_ms_ = 0;
  uint64_t retries_ = 0, lost_ = 0;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace amb::fw
