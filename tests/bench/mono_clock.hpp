#pragma once
// The loop benchmarks' clock: CLOCK_MONOTONIC read and absolute-deadline sleeps
// (clock_nanosleep TIMER_ABSTIME), what hal/linux's clock does, on absolute time so a front end
// can stamp its samples with the same clock.
#include <time.h>

#include <cstdint>

#include "hal/interfaces.hpp"

namespace amb::bench {

/// CLOCK_MONOTONIC now, ns.
inline int64_t mono_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

class MonoClock final : public hal::Clock {
 public:
  int64_t now_ns() override { return mono_ns(); }
  int64_t wait_until_ns(int64_t deadline_ns) override {
    timespec ts{static_cast<time_t>(deadline_ns / 1'000'000'000), static_cast<long>(deadline_ns % 1'000'000'000)};
    while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
    }
    return mono_ns();
  }
};

}  // namespace amb::bench
