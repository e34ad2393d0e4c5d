#pragma once
// Real-time set-up of the calling (loop) thread on Linux/PREEMPT_RT: locked memory, a
// pre-faulted stack, SCHED_FIFO and a fixed CPU. Called once at configure, never in the loop.
#include <string>

namespace amb::hal::linux_hw {

struct RtOptions {
  int fifo_priority = 80;        ///< SCHED_FIFO priority, 1..99 (0: keep the normal scheduler)
  int cpu = -1;                  ///< CPU to pin the thread to (-1: no affinity change)
  bool lock_memory = true;       ///< mlockall(MCL_CURRENT | MCL_FUTURE)
  size_t prefault_stack_bytes = 256 * 1024;  ///< stack touched up front so the loop never page-faults
};

/// What was applied; `warnings` lists settings that could not be applied (e.g. no
/// CAP_SYS_NICE on a development host) — the caller decides whether that is fatal.
struct RtReport {
  bool memory_locked = false;
  bool fifo = false;
  bool pinned = false;
  std::string warnings;
};

RtReport configure_realtime_thread(const RtOptions& options);

}  // namespace amb::hal::linux_hw
