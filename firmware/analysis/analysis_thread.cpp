#include "firmware/analysis/analysis_thread.hpp"

#include <chrono>

namespace amb::fw {

void AnalysisThread::start(AnalysisTask& task, double poll_period_s, StatusCallback on_status, double status_period_s) {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this, &task, poll_period_s, status_period_s, cb = std::move(on_status)] {
    // Background work: below every ordinary thread of the board (the linux backend: nice 10),
    // so that it only takes what the loop, the field bus and the link leave (on the emulated
    // board also the HIL plant process sharing the CPUs). Not fatal if refused.
    if (scheduling_) (void)scheduling_->make_current_thread_background();
    using clock = std::chrono::steady_clock;
    const auto poll_period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(poll_period_s));
    const auto status_period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(status_period_s));
    auto next_poll = clock::now();
    auto next_status = next_poll + status_period;
    while (running_.load(std::memory_order_relaxed)) {
      task.poll();
      const auto now = clock::now();
      if (cb && now >= next_status) {
        cb(task.status());
        next_status += status_period;
        if (next_status < now) next_status = now + status_period;
      }
      next_poll += poll_period;
      if (next_poll < now) next_poll = now;  // fell behind: do not burst
      std::this_thread::sleep_until(next_poll);
    }
    task.poll();
  });
}

void AnalysisThread::stop() {
  if (!running_.exchange(false)) return;
  if (thread_.joinable()) thread_.join();
}

}  // namespace amb::fw
