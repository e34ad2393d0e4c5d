#pragma once
// Classical fixed-step 4th-order Runge-Kutta on fixed-size Eigen vectors (no allocation).
//
// Step control is deliberately fixed, not adaptive: the groove defects make the right-hand
// side discontinuous in time, where an embedded error estimate makes the step collapse at
// every ball passage. Callers choose h from the physics instead (see choose_step_s in
// hertz_4dof.hpp): a fraction of the fastest linearised period and of the defect transit
// time, and an integer divisor of the output sample period.
#include <Eigen/Core>

namespace amb::model::bearing {

/// Advance y(t) by h with derivative f(t, y) -> dy/dt. Returns k1 = f(t, y) (the derivative at
/// the start of the step), which callers use to read accelerations at sample instants.
template <int N, typename F>
Eigen::Matrix<double, N, 1> rk4_step(F&& f, double t, Eigen::Matrix<double, N, 1>& y, double h) {
  using V = Eigen::Matrix<double, N, 1>;
  const V k1 = f(t, y);
  const V k2 = f(t + 0.5 * h, V(y + 0.5 * h * k1));
  const V k3 = f(t + 0.5 * h, V(y + 0.5 * h * k2));
  const V k4 = f(t + h, V(y + h * k3));
  y += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  return k1;
}

}  // namespace amb::model::bearing
