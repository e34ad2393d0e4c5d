#include "firmware/events/event_writer.hpp"

#include <chrono>

#include "firmware/analysis/analysis_task.hpp"
#include "firmware/events/event_codec.hpp"

namespace amb::fw {

EventWriter::EventWriter(FloatingCapture& capture, hal::Storage& storage, const board::BoardConfig& board,
                         WriterOptions options)
    : capture_(capture), board_(board), o_(options), store_(storage, board.capture) {
  if (board.bearing.present) bearing_.configure(bearing_task_config(board));
}

EventWriter::~EventWriter() { stop(); }

void EventWriter::start() {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this] {
    while (running_.load(std::memory_order_relaxed)) {
      if (poll() == 0) std::this_thread::sleep_for(std::chrono::milliseconds(o_.idle_sleep_ms));
    }
    poll();
  });
}

void EventWriter::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

size_t EventWriter::poll() {
  size_t done = 0;
  while (const FrozenEvent* e = capture_.take()) {
    // Copy out and hand the buffer back first: the loop can capture again while we work.
    const uint64_t number = store_.next_number();
    EventRecord r = make_event_record(*e, board_, number);
    capture_.release(e);
    if (o_.run_diagnosis) {
      r.diagnosis = diag::diagnose(diagnosis_input(r), o_.diagnosis);
      r.has_diagnosis = true;
    }
    r.analysis = event_analysis(r, board_, bearing_);
    r.has_analysis = true;
    const std::vector<uint8_t> bytes = encode_event(r);
    std::string error;
    bool stored = false;
    {
      std::lock_guard<std::mutex> lock(m_);
      stored = store_.store(number, bytes, error);
      if (!stored) last_error_ = error;
    }
    if (on_event) on_event(r, EventStore::name_of(number), stored);
    ++done;
  }
  return done;
}

StoreCounters EventWriter::store_counters() const {
  std::lock_guard<std::mutex> lock(m_);
  return store_.counters();
}

std::string EventWriter::last_error() const {
  std::lock_guard<std::mutex> lock(m_);
  return last_error_;
}

}  // namespace amb::fw
