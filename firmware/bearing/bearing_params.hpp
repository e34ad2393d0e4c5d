#pragma once
// Board-file settings of the on-board bearing task ([bearing] table, optional): the
// monitored rolling bearing whose defect lines are computed at the tracked speed, and the
// constants of the quick-look auxiliary-bearing load estimate run after each drop event.
#include <string>

namespace amb::fw {

struct BearingParams {
  bool present = false;                     ///< the board file has a [bearing] table
  std::string monitored;                    ///< catalogue name of the monitored bearing (model/bearing/catalogue)
  double radial_clearance_m = 5e-6;         ///< monitored bearing radial clearance, m
  double min_speed_hz = 1.0;                ///< defect lines only between min and max speed, Hz
  double max_speed_hz = 1000.0;             ///< Hz
  double aux_contact_constant_n_per_m1p5 = 0.0;  ///< Hertz constant K of the rotor/aux-race contact, N/m^1.5
  double aux_dynamic_load_rating_n = 0.0;   ///< dynamic load rating C of an aux bearing, N
  /// Aux inner-race spin assumed during contact, Hz; 0: the speed at the trigger (tracked
  /// or tach, whichever is the board's speed source).
  double aux_spin_speed_hz = 0.0;
};

}  // namespace amb::fw
