#pragma once
// The non-real-time event thread: takes frozen windows from the capture, runs Phase B and the
// bearing task's quick-look aux-bearing load on each, encodes it (AMBE v2) and stores it,
// then gives the buffer back to the loop.
// The loop never waits for it: if it falls behind, the capture loses (and counts) events.
#include <atomic>
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
#include "hal/interfaces.hpp"

namespace amb::fw {

struct WriterOptions {
  bool run_diagnosis = true;          ///< Phase B on every event
  diag::DiagnosisOptions diagnosis;   ///< its thresholds
  int idle_sleep_ms = 5;              ///< thread: sleep when nothing is waiting, ms
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
  /// the record (with diagnosis), its file name, whether it was stored.
  std::function<void(const EventRecord&, const std::string& name, bool stored)> on_event;

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
  mutable std::mutex m_;  ///< guards store_ counters and last_error_ for readers in other threads
  std::string last_error_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace amb::fw
