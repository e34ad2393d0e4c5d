#include "firmware/control/axis_transform.hpp"

#include <cmath>

namespace amb::fw {
namespace {
std::array<double, 4> inverse2(double a, double b, double c, double d) {
  const double det = a * d - b * c;
  return {d / det, -b / det, -c / det, a / det};
}
double rad(double deg) { return deg * M_PI / 180.0; }
}  // namespace

void AxisTransform::configure(const std::array<double, 2>& sensor_deg,
                              const std::array<double, 2>& actuator_deg) {
  const double s1 = rad(sensor_deg[0]), s2 = rad(sensor_deg[1]);
  s_inv_ = inverse2(std::sin(s1), std::cos(s1), std::sin(s2), std::cos(s2));
  const double b1 = rad(actuator_deg[0]), b2 = rad(actuator_deg[1]);
  // F_xy = [u1 u2] f, with u_j = (sin b_j, cos b_j) as columns.
  a_inv_ = inverse2(std::sin(b1), std::sin(b2), std::cos(b1), std::cos(b2));
}

std::array<double, 2> AxisTransform::sensors_to_xy(const std::array<double, 2>& s) const {
  return {s_inv_[0] * s[0] + s_inv_[1] * s[1], s_inv_[2] * s[0] + s_inv_[3] * s[1]};
}

std::array<double, 2> AxisTransform::xy_to_actuators(const std::array<double, 2>& f) const {
  return {a_inv_[0] * f[0] + a_inv_[1] * f[1], a_inv_[2] * f[0] + a_inv_[3] * f[1]};
}

}  // namespace amb::fw
