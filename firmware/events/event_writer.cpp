#include "firmware/events/event_writer.hpp"

#include <algorithm>
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
  // Events still waiting after the thread's last poll: one more attempt each, then lost.
  flush_pending(std::chrono::steady_clock::time_point::max());
  std::lock_guard<std::mutex> lock(m_);
  lost_ += pending_.size();
  pending_.clear();
}

void EventWriter::enqueue(uint64_t number, std::vector<uint8_t> bytes) {
  std::lock_guard<std::mutex> lock(m_);
  if (static_cast<int>(pending_.size()) >= std::max(1, o_.max_pending)) {
    ++lost_;
    if (board_.capture.storage_policy == StoragePolicy::refuse_new) {
      last_error_ = "event " + std::to_string(number) + " lost: retry queue full (" + last_error_ + ")";
      return;
    }
    last_error_ = "event " + std::to_string(pending_.front().number) + " lost: retry queue full (" + last_error_ + ")";
    pending_.pop_front();
  }
  pending_.push_back(Pending{number, std::move(bytes)});
}

size_t EventWriter::flush_pending(std::chrono::steady_clock::time_point now) {
  size_t left = 0;
  while (!pending_.empty() && now >= next_retry_) {
    std::string error;
    std::lock_guard<std::mutex> lock(m_);
    ++retries_;
    const StoreResult r = store_.put(pending_.front().number, pending_.front().bytes, error);
    if (r == StoreResult::failed) {
      last_error_ = error;
      backoff_ms_ = std::min(std::max(o_.retry_initial_ms, 2 * backoff_ms_), o_.retry_max_ms);
      next_retry_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(backoff_ms_);
      break;
    }
    if (r == StoreResult::refused) last_error_ = error;
    pending_.pop_front();
    ++left;
  }
  if (pending_.empty()) backoff_ms_ = 0;
  return left;
}

size_t EventWriter::poll() {
  size_t done = flush_pending(std::chrono::steady_clock::now());
  while (const FrozenEvent* e = capture_.take()) {
    // Copy out and hand the buffer back first: the loop can capture again while we work.
    const uint64_t number = store_.reserve_number();
    EventRecord r = make_event_record(*e, board_, number);
    capture_.release(e);
    if (o_.run_diagnosis) {
      r.diagnosis = diag::diagnose(diagnosis_input(r), o_.diagnosis);
      r.has_diagnosis = true;
    }
    r.analysis = event_analysis(r, board_, bearing_);
    r.has_analysis = true;
    const StoreResult result = store_or_queue(number, encode_event(r));
    if (on_event) on_event(r, EventStore::name_of(number), result == StoreResult::stored);
    ++done;
  }
  if (sweep_ && sweep_->ready()) {
    // A finished sweep: copy it out, hand the buffer back, then encode and store.
    const uint64_t number = store_.reserve_number();
    const SweepEvent ev = make_sweep_event(sweep_->view(), board_, number);
    sweep_->release();
    const StoreResult result = store_or_queue(number, encode_sweep_event(ev));
    if (result == StoreResult::stored) {
      sweeps_stored_.fetch_add(1);
      last_sweep_number_.store(number);
    }
    if (on_sweep) on_sweep(ev, EventStore::name_of(number), result == StoreResult::stored);
    ++done;
  }
  return done;
}

StoreResult EventWriter::store_or_queue(uint64_t number, std::vector<uint8_t> bytes) {
  std::string error;
  StoreResult result = StoreResult::failed;
  if (pending_.empty()) {  // in order: behind the events already waiting
    std::lock_guard<std::mutex> lock(m_);
    result = store_.put(number, bytes, error);
    if (result != StoreResult::stored) last_error_ = error;
    if (result == StoreResult::failed) {
      backoff_ms_ = o_.retry_initial_ms;
      next_retry_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(backoff_ms_);
    }
  }
  if (result == StoreResult::failed) enqueue(number, std::move(bytes));
  return result;
}

StoreCounters EventWriter::store_counters() const {
  std::lock_guard<std::mutex> lock(m_);
  StoreCounters c = store_.counters();
  c.retries = retries_;
  c.pending = pending_.size();
  c.lost = lost_;
  return c;
}

std::string EventWriter::last_error() const {
  std::lock_guard<std::mutex> lock(m_);
  return last_error_;
}

}  // namespace amb::fw
