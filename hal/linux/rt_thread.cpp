#include "hal/linux/rt_thread.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace amb::hal::linux_hw {

namespace {
// Touch a stack region so its pages are resident before the loop starts (the lock that
// follows then keeps them resident).
__attribute__((noinline)) void prefault_stack(size_t bytes) {
  volatile unsigned char* buf = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  for (size_t i = 0; i < bytes; i += 4096) buf[i] = 0;
}
void add(std::string& w, const std::string& s) { w += (w.empty() ? "" : "; ") + s; }

/// The highest CPU of the process's affinity set, -1 if the set has fewer than two CPUs.
int highest_allowed_cpu() {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (::sched_getaffinity(0, sizeof allowed, &allowed) != 0 || CPU_COUNT(&allowed) < 2) return -1;
  for (int c = CPU_SETSIZE - 1; c >= 0; --c)
    if (CPU_ISSET(c, &allowed)) return c;
  return -1;
}
}  // namespace

RtReport configure_realtime_thread(const RtOptions& o) {
  RtReport r;
  // Stack first, then the lock: MCL_CURRENT locks what is mapped now, the pre-faulted stack with it.
  if (o.prefault_stack_bytes > 0) prefault_stack(o.prefault_stack_bytes);
  if (o.lock_memory) {
    const int flags = MCL_CURRENT | (o.lock_future ? MCL_FUTURE : 0);
    if (::mlockall(flags) == 0) r.memory_locked = true;
    else add(r.warnings, std::string("mlockall: ") + std::strerror(errno));
  }
  const int cpu = o.cpu >= 0 ? o.cpu : (o.pin_highest_allowed ? highest_allowed_cpu() : -1);
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    const int e = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    if (e == 0) {
      r.pinned = true;
      r.cpu = cpu;
    } else {
      add(r.warnings, "affinity to CPU " + std::to_string(cpu) + ": " + std::strerror(e));
    }
  }
  if (o.fifo_priority > 0) {
    sched_param sp{};
    sp.sched_priority = o.fifo_priority;
    const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (e == 0) r.fifo = true;
    else add(r.warnings, "SCHED_FIFO priority " + std::to_string(o.fifo_priority) + ": " + std::strerror(e));
  }
  return r;
}

}  // namespace amb::hal::linux_hw
