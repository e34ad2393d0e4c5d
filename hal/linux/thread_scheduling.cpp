#include "hal/linux/thread_scheduling.hpp"

#include <sys/resource.h>
#include <unistd.h>

namespace amb::hal::linux_hw {

bool LinuxThreadScheduling::make_current_thread_background() {
  return ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), background_nice_) == 0;
}

}  // namespace amb::hal::linux_hw
