#pragma once
// Real-time set-up of the calling (loop) thread on Linux/PREEMPT_RT: a pre-faulted stack,
// locked memory, SCHED_FIFO and a fixed CPU. Called once at configure, never in the loop.
#include <cstddef>
#include <string>

namespace amb::hal::linux_hw {

struct RtOptions {
  int fifo_priority = 80;        ///< SCHED_FIFO priority, 1..99 (0: keep the normal scheduler)
  int cpu = -1;                  ///< CPU to pin the thread to (-1: see pin_highest_allowed)
  /// With cpu == -1: pin to the highest CPU the process may use (the service's CPUAffinity= or
  /// taskset chooses the set) when the set has at least two CPUs; the other threads share the
  /// rest. A one-CPU set is left alone.
  bool pin_highest_allowed = false;
  bool lock_memory = true;       ///< mlockall(MCL_CURRENT), after the stack is pre-faulted
  /// Also MCL_FUTURE: every later mapping (thread stacks, malloc growth, libraries) is locked
  /// and populated as it appears. Only needed when memory the thread uses is mapped after this
  /// call; the firmware's loop allocates everything before (configure), so it leaves this off.
  bool lock_future = false;
  size_t prefault_stack_bytes = 256 * 1024;  ///< stack touched up front so the loop never page-faults, bytes
};

/// What was applied; `warnings` lists settings that could not be applied (e.g. no
/// CAP_SYS_NICE on a development host) — the caller decides whether that is fatal.
struct RtReport {
  bool memory_locked = false;
  bool fifo = false;
  bool pinned = false;
  int cpu = -1;                  ///< CPU pinned to (-1: none)
  std::string warnings;
};

RtReport configure_realtime_thread(const RtOptions& options);

}  // namespace amb::hal::linux_hw
