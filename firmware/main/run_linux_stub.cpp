// Replaced by the linux backend run mode when hal/linux provides it (AMB_HAVE_LINUX_RUN).
#include <cstdio>

#include "firmware/main/run_modes.hpp"

#ifndef AMB_HAVE_LINUX_RUN
namespace amb::fwmain {
int run_linux(const board::BoardConfig& board, const RunOptions&) {
  std::fprintf(stderr, "amb-firmware: board %s asks for the linux backend, which this build lacks\n",
               board.name.c_str());
  return 1;
}
}  // namespace amb::fwmain
#endif
