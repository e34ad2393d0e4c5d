#pragma once
// The sensor view of the orbit at the auxiliary-bearing planes: the two +-45 deg sensor
// pairs give (x, y) at the two sensor planes; the aux-bearing planes lie outboard of them,
// so the rotor centre there is extrapolated along the straight line through the two sensor
// planes (rigid-rotor assumption: bending between the planes is not seen). Measurement and
// simulation both go through this view before they are compared.
#include <array>

#include "model/plant/plant_params.hpp"

namespace amb::model::drop {

class SensorOrbit {
 public:
  /// Throws std::invalid_argument when the sensor pairs are parallel or share one plane.
  explicit SensorOrbit(const PlantParams& p);
  /// Sensor readings [A1, A2, B1, B2] (m) -> (x, y) at sensor plane `pair` (0: A, 1: B), m.
  std::array<double, 2> at_sensor_plane(const std::array<double, 4>& readings_m, int pair) const;
  /// Readings (m) -> rotor centre (x, y) at aux-bearing plane `bearing`, m (sensor frame).
  std::array<double, 2> at_aux_plane(const std::array<double, 4>& readings_m, int bearing) const;

 private:
  std::array<std::array<double, 4>, 2> inv_{};  // per pair, inverse of [[sin a1, cos a1], [sin a2, cos a2]]
  std::array<double, 2> sensor_z_{}, aux_z_{};
};

}  // namespace amb::model::drop
