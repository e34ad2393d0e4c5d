#pragma once
// The +-45 deg sensor/actuator axis transformation of one radial bearing plane.
// Angles are measured from the upward vertical, positive towards +x: a reading along an
// axis at angle a is s = x sin(a) + y cos(a).
#include <array>

namespace amb::fw {

class AxisTransform {
 public:
  /// `sensor_deg`: directions of the two sensors; `actuator_deg`: directions of the two
  /// actuator axes. Both pairs must be non-parallel (validated by the board loader).
  void configure(const std::array<double, 2>& sensor_deg, const std::array<double, 2>& actuator_deg);
  /// Sensor readings (m) -> (x, y) in the bearing frame (m).
  std::array<double, 2> sensors_to_xy(const std::array<double, 2>& s_m) const;
  /// Force demand (Fx, Fy) in N -> force per actuator axis, N.
  std::array<double, 2> xy_to_actuators(const std::array<double, 2>& f_n) const;

 private:
  std::array<double, 4> s_inv_{1, 0, 0, 1};  ///< inverse of [[sin a1, cos a1], [sin a2, cos a2]]
  std::array<double, 4> a_inv_{1, 0, 0, 1};  ///< inverse of [[sin b1, sin b2], [cos b1, cos b2]]
};

}  // namespace amb::fw
