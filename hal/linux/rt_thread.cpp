#include "hal/linux/rt_thread.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace amb::hal::linux_hw {

namespace {
// Touch a stack region so its pages are resident before the loop starts (with mlockall
// they then stay resident).
__attribute__((noinline)) void prefault_stack(size_t bytes) {
  volatile unsigned char* buf = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  for (size_t i = 0; i < bytes; i += 4096) buf[i] = 0;
}
void add(std::string& w, const std::string& s) { w += (w.empty() ? "" : "; ") + s; }
}  // namespace

RtReport configure_realtime_thread(const RtOptions& o) {
  RtReport r;
  if (o.lock_memory) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) r.memory_locked = true;
    else add(r.warnings, std::string("mlockall: ") + std::strerror(errno));
  }
  if (o.prefault_stack_bytes > 0) prefault_stack(o.prefault_stack_bytes);
  if (o.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(o.cpu, &set);
    const int e = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    if (e == 0) r.pinned = true;
    else add(r.warnings, "affinity to CPU " + std::to_string(o.cpu) + ": " + std::strerror(e));
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
