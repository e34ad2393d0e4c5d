#pragma once
// The ISO 14839-3 rating of a board's loop with its own computation/transport delay (issue 38):
// the exact sampled closed loop (model/analysis/closed_loop.hpp) at standstill, the board's
// controller, rate and [controller] loop_delay_periods. Host side; allocates.
#include <string>
#include <vector>

#include "firmware/board/board.hpp"

namespace amb::host {

struct LoopRating {
  double rate_hz = 0.0;             ///< loop rate, Hz
  double loop_delay_periods = 0.0;  ///< the board's delay, periods
  bool stable = false;              ///< every closed-loop pole inside the unit circle
  double sensitivity_peak = 0.0;    ///< worst |S| over the four actuator axes, 0.1 Hz .. Nyquist
  double sensitivity_peak_db = 0.0; ///< 20 log10 of it
  double peak_hz = 0.0;             ///< where, Hz
  int peak_axis = 0;                ///< which actuator axis (0..3: A1, A2, B1, B2)
  std::string zone;                 ///< ISO 14839-3 zone, "A".."D"
  std::vector<double> rotor_mode_hz;    ///< rotor-dominated closed-loop modes, Hz (x/y merged)
  std::vector<double> rotor_mode_zeta;  ///< their damping ratios
};

/// Rate `board`'s loop. Throws std::invalid_argument if its rig cannot be built.
LoopRating rate_loop(const board::BoardConfig& board);

}  // namespace amb::host
