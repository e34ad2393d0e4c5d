#include "model/drop/sensor_orbit.hpp"

#include <cmath>
#include <stdexcept>

#include "model/amb/amb_force.hpp"

namespace amb::model::drop {

SensorOrbit::SensorOrbit(const PlantParams& p) {
  for (size_t k = 0; k < 2; ++k) {
    const auto s0 = magnet::axis_direction(p.sensor[2 * k].angle_deg);
    const auto s1 = magnet::axis_direction(p.sensor[2 * k + 1].angle_deg);
    const double det = s0[0] * s1[1] - s0[1] * s1[0];
    if (std::abs(det) < 1e-9) throw std::invalid_argument("sensor orbit: sensors of a pair are parallel");
    if (std::abs(p.sensor[2 * k].axial_m - p.sensor[2 * k + 1].axial_m) > 1e-3)
      throw std::invalid_argument("sensor orbit: the two sensors of a pair are not in one plane");
    inv_[k] = {s1[1] / det, -s0[1] / det, -s1[0] / det, s0[0] / det};
    sensor_z_[k] = p.sensor[2 * k].axial_m;
    aux_z_[k] = p.aux[k].axial_m;
  }
  if (std::abs(sensor_z_[1] - sensor_z_[0]) < 1e-3) throw std::invalid_argument("sensor orbit: both sensor planes coincide");
}

std::array<double, 2> SensorOrbit::at_sensor_plane(const std::array<double, 4>& r, int pair) const {
  const size_t k = static_cast<size_t>(pair);
  const auto& v = inv_[k];
  const double a = r[2 * k], b = r[2 * k + 1];
  return {v[0] * a + v[1] * b, v[2] * a + v[3] * b};
}

std::array<double, 2> SensorOrbit::at_aux_plane(const std::array<double, 4>& r, int bearing) const {
  const auto p0 = at_sensor_plane(r, 0), p1 = at_sensor_plane(r, 1);
  const double s = (aux_z_[static_cast<size_t>(bearing)] - sensor_z_[0]) / (sensor_z_[1] - sensor_z_[0]);
  return {p0[0] + s * (p1[0] - p0[0]), p0[1] + s * (p1[1] - p0[1])};
}

}  // namespace amb::model::drop
