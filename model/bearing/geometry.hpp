#pragma once
// Rolling-bearing geometry and kinematic (no-slip) characteristic frequencies.
//
// Conventions: gamma = (D_b / D_m) cos(alpha), with D_b the ball diameter, D_m the pitch
// diameter and alpha the contact angle. Outer race stationary, inner race turning with the
// shaft at f_r. Then, per shaft Hz:
//   FTF  (cage)            = (1 - gamma) / 2
//   BPFO (outer-race pass) = Z/2 (1 - gamma)
//   BPFI (inner-race pass) = Z/2 (1 + gamma)
//   BSF  (ball spin)       = D_m / (2 D_b) (1 - gamma^2)
// Seed 001 eq. (16) prints BPFO as Z/2 (1 + gamma) f; that is a typo in the extracted text:
// its own figure (101.6 Hz at 2000 rpm) needs (1 - gamma). Seed 001 Table 5 also lists a
// contact angle of 49.3 deg, but its 762 rpm cage figure needs alpha = 0 (deep-groove).
#include <string_view>

namespace amb::model::bearing {

/// Geometry of a radial ball bearing.
struct BearingGeometry {
  std::string_view name;           ///< catalogue name, e.g. "SKF 6205"
  int ball_count = 0;              ///< number of rolling elements Z, dimensionless (>= 3)
  double ball_diameter_m = 0.0;    ///< ball diameter D_b, m
  double pitch_diameter_m = 0.0;   ///< pitch (cage centre-circle) diameter D_m, m
  double contact_angle_rad = 0.0;  ///< nominal contact angle alpha, rad (0 for deep-groove)
  std::string_view source;         ///< where the numbers come from; "ASSUMED" marks guesses

  /// gamma = D_b cos(alpha) / D_m, dimensionless.
  double gamma() const;
  /// Outer raceway (groove bottom) radius, m: (D_m + D_b) / 2.
  double outer_raceway_radius_m() const { return 0.5 * (pitch_diameter_m + ball_diameter_m); }
  /// Inner raceway (groove bottom) radius, m: (D_m - D_b) / 2.
  double inner_raceway_radius_m() const { return 0.5 * (pitch_diameter_m - ball_diameter_m); }
  /// True if the numbers are physically meaningful (Z >= 3, 0 < D_b < D_m, |alpha| < 90 deg).
  bool valid() const;
};

/// Characteristic frequencies as multiples of the shaft rotation frequency (dimensionless).
struct DefectOrders {
  double ftf = 0.0;   ///< cage (fundamental train) frequency / shaft frequency
  double bpfo = 0.0;  ///< outer-race ball-pass frequency / shaft frequency
  double bpfi = 0.0;  ///< inner-race ball-pass frequency / shaft frequency
  double bsf = 0.0;   ///< ball spin frequency (relative to the cage) / shaft frequency
};

/// Characteristic frequencies in Hz at a given shaft speed.
struct DefectFrequencies {
  double shaft_hz = 0.0;  ///< shaft rotation frequency, Hz
  double ftf_hz = 0.0;    ///< cage frequency, Hz
  double bpfo_hz = 0.0;   ///< outer-race defect frequency, Hz
  double bpfi_hz = 0.0;   ///< inner-race defect frequency, Hz
  double bsf_hz = 0.0;    ///< ball spin frequency, Hz (a ball defect shows mostly at 2*bsf_hz)
};

/// Kinematic orders of `g` (outer race fixed, no slip).
DefectOrders defect_orders(const BearingGeometry& g);

/// Kinematic frequencies of `g` at shaft speed `shaft_speed_hz` (Hz, may be negative).
DefectFrequencies defect_frequencies(const BearingGeometry& g, double shaft_speed_hz);

/// Cage speed for general inner- and outer-race speeds (seed 001 eq. 14), any consistent unit
/// (rpm in, rpm out): ((1 - gamma) w_inner + (1 + gamma) w_outer) / 2.
double cage_speed(const BearingGeometry& g, double inner_speed, double outer_speed);

/// Ball spin speed about its own axis (seed 001 eq. 15), same unit as the inputs:
/// D_m / (2 D_b) (w_outer - w_inner)(1 - gamma^2). Negative when the inner race leads.
double ball_spin_speed(const BearingGeometry& g, double inner_speed, double outer_speed);

}  // namespace amb::model::bearing
