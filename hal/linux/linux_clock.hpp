#pragma once
// CLOCK_MONOTONIC time and absolute-time sleeps (clock_nanosleep TIMER_ABSTIME).
#include <cstdint>

#include "hal/interfaces.hpp"

namespace amb::hal::linux_hw {

class LinuxClock final : public Clock {
 public:
  /// The epoch (time 0) is CLOCK_MONOTONIC at construction.
  LinuxClock();
  /// [RT] ns since the epoch (vDSO clock_gettime, no system call on arm64/x86-64).
  int64_t now_ns() override;
  /// [RT] Sleep until the absolute `deadline_ns` (since the epoch); returns the time woken, ns.
  int64_t wait_until_ns(int64_t deadline_ns) override;

 private:
  int64_t epoch_ns_ = 0;
};

/// CLOCK_MONOTONIC now, ns (absolute, for code that needs no epoch).
int64_t monotonic_ns();

}  // namespace amb::hal::linux_hw
