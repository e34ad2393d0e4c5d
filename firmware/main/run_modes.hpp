#pragma once
// The run modes of amb-firmware, one file each.
#include <string>

#include "firmware/board/board.hpp"

namespace amb::fwmain {

struct RunOptions {
  std::string board;        ///< board name or path
  double duration_s = -1.0; ///< <0: mode default
  bool paced = false;       ///< sim: pace to wall time
  bool spin = true;         ///< sim: spin up to the operating speed
  bool analysis = true;     ///< run the analysis thread (tracker, bearing task) when the board enables the tracker
  bool sweep = false;       ///< sim: run the loop-sensitivity sweep ([sweep]) once levitated / at speed
};

/// Software in the loop: levitate, spin up, hold, land; prints a summary. Exit code.
int run_sim(const board::BoardConfig& board, const RunOptions& opt);

/// Real I/O (SocketCAN, libgpiod, libmodbus) on the board. Exit code.
int run_linux(const board::BoardConfig& board, const RunOptions& opt);

}  // namespace amb::fwmain
