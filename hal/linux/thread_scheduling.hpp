#pragma once
// hal::ThreadScheduling on Linux: nice values for the board's ordinary threads.
#include "hal/interfaces.hpp"

namespace amb::hal::linux_hw {

class LinuxThreadScheduling final : public ThreadScheduling {
 public:
  /// `background_nice`: nice value of a background thread, 1..19 (10: below every ordinary
  /// thread at the default 0, above nothing else).
  explicit LinuxThreadScheduling(int background_nice = 10) : background_nice_(background_nice) {}
  /// setpriority(PRIO_PROCESS, gettid(), background_nice): on Linux a nice value is per thread.
  bool make_current_thread_background() override;

 private:
  int background_nice_;
};

}  // namespace amb::hal::linux_hw
