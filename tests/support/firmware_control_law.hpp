#pragma once
// The firmware's control law run outside the firmware, for tests that drive a plant or the sim
// backend themselves (an injection, a benchmark of the plant): per plane the +-45 deg axis
// transform (fw::AxisTransform), per direction the PID with its notches (fw::PidAxis), the four
// sensor readings in, the four current demands out -- the loop step's arithmetic without the
// supervisor, the capture or the HAL.
#include <array>
#include <cstddef>

#include "firmware/board/board.hpp"
#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"

namespace amb::test {

class FirmwareControlLaw {
 public:
  /// Configured from the board's controller and rate, with the sensor / actuator angles and
  /// current gains of `plant` (the board's plant, not a simulated truth). State cleared.
  FirmwareControlLaw(const board::BoardConfig& b, const model::PlantParams& plant) : plant_(plant) {
    for (size_t p = 0; p < 2; ++p) {
      xf_[p].configure({plant.sensor[2 * p].angle_deg, plant.sensor[2 * p + 1].angle_deg}, plant.amb[p].actuator_angle_deg);
      for (size_t d = 0; d < 2; ++d) pid_[2 * p + d].configure(b.controller, b.rate_hz, plant.amb[p].ki_n_per_a);
    }
  }

  /// One period: sensor readings [A1, A2, B1, B2] (m, set-point 0) -> current demands per
  /// actuator axis [A1, A2, B1, B2], A.
  template <class Readings>
  std::array<double, 4> demands_a(const Readings& sensor_m) {
    std::array<double, 4> i_a{};
    for (size_t p = 0; p < 2; ++p) {
      const auto xy = xf_[p].sensors_to_xy({static_cast<double>(sensor_m[2 * p]), static_cast<double>(sensor_m[2 * p + 1])});
      bool saturated = false;
      const double fx = pid_[2 * p].step(xy[0], 0.0, saturated), fy = pid_[2 * p + 1].step(xy[1], 0.0, saturated);
      const auto f = xf_[p].xy_to_actuators({fx, fy});
      i_a[2 * p] = f[0] / plant_.amb[p].ki_n_per_a;
      i_a[2 * p + 1] = f[1] / plant_.amb[p].ki_n_per_a;
    }
    return i_a;
  }

  /// The PID of direction i (2 * plane + direction, x then y), e.g. to preload an integrator.
  fw::PidAxis& pid(size_t i) { return pid_[i]; }

 private:
  model::PlantParams plant_;
  std::array<fw::AxisTransform, 2> xf_{};
  std::array<fw::PidAxis, 4> pid_{};
};

}  // namespace amb::test
