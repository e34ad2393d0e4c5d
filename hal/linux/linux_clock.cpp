#include "hal/linux/linux_clock.hpp"

#include <cerrno>
#include <ctime>

namespace amb::hal::linux_hw {

int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

LinuxClock::LinuxClock() : epoch_ns_(monotonic_ns()) {}

int64_t LinuxClock::now_ns() { return monotonic_ns() - epoch_ns_; }

int64_t LinuxClock::wait_until_ns(int64_t deadline_ns) {
  const int64_t abs_ns = deadline_ns + epoch_ns_;
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(abs_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(abs_ns % 1'000'000'000);
  // Absolute sleep: a signal only shortens it, so repeat until the deadline (no drift).
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
  return now_ns();
}

}  // namespace amb::hal::linux_hw
