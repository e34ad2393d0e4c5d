#pragma once
// The analysis thread: calls AnalysisTask::poll() every poll period and, every status
// period, hands the newest analysis and loop status to a callback (the linux backend sends
// the CAN board-status frame from it). Ordinary (non-real-time) thread, put in the background
// by the backend's hal::ThreadScheduling (linux: nice 10, below the board's other ordinary
// threads); the loop never waits for it. The sim backend uses the same thread in
// `amb-firmware --backend sim` (no scheduling there).
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>

#include "firmware/analysis/analysis_task.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

class AnalysisThread {
 public:
  using StatusCallback = std::function<void(const AnalysisStatus&)>;
  /// `scheduling`: the backend's, applied by the thread to itself when it starts (nullptr:
  /// none, the thread keeps the scheduling it inherits); must outlive the thread.
  explicit AnalysisThread(hal::ThreadScheduling* scheduling = nullptr) : scheduling_(scheduling) {}
  AnalysisThread(const AnalysisThread&) = delete;
  AnalysisThread& operator=(const AnalysisThread&) = delete;
  ~AnalysisThread() { stop(); }

  /// Start polling `task` every `poll_period_s` (s, > 0); `on_status` (optional) is called in
  /// the thread every `status_period_s` (s). `task` must outlive the thread.
  void start(AnalysisTask& task, double poll_period_s, StatusCallback on_status = {}, double status_period_s = 0.1);
  /// Stop and join (drains once more).
  void stop();
  bool running() const { return running_.load(std::memory_order_relaxed); }
  /// The thread's handle (for its CPU clock, read by a supervision thread); valid while running.
  std::thread::native_handle_type native_handle() { return thread_.native_handle(); }

 private:
  hal::ThreadScheduling* scheduling_ = nullptr;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace amb::fw
