#include "firmware/analysis/analysis_thread.hpp"

#include <chrono>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace amb::fw {

void AnalysisThread::start(AnalysisTask& task, double poll_period_s, StatusCallback on_status, double status_period_s) {
  if (running_.exchange(true)) return;
  thread_ = std::thread([this, &task, poll_period_s, status_period_s, cb = std::move(on_status)] {
#if defined(__linux__)
    // Background work: below every ordinary thread of the board (nice 10), so that it only takes
    // what the loop, the field bus and the link leave (on the emulated board also the HIL plant
    // process sharing the CPUs). Not fatal if refused.
    (void)::setpriority(PRIO_PROCESS, static_cast<id_t>(::syscall(SYS_gettid)), 10);
#endif
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
