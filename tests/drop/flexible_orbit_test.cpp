// The rigid-body part of a flexible rotor's orbit (model/drop/flexible_orbit.hpp): on the
// Bath rig's FE rotor, checked against a simulation of the same modal model driven by known
// forces at the aux planes, and the stability of the inverse per number of bending modes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "firmware/board/board.hpp"
#include "model/drop/flexible_orbit.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "tests/support/bath_board.hpp"

using amb::test::bath_board;

namespace {

namespace mr = amb::model::rotor;

std::array<double, 2> sensor_planes(const amb::model::PlantParams& p) { return {p.sensor[0].axial_m, p.sensor[2].axial_m}; }
std::array<double, 2> aux_planes(const amb::model::PlantParams& p) { return {p.aux[0].axial_m, p.aux[1].axial_m}; }

// The first bending mode can be inverted from the two sensor planes (the sensors lie inboard
// of the aux bearings, close to them); with the second, whose shape has nodes between the
// planes, the path from the aux-plane forces to the sensors is not minimum-phase.
TEST(FlexibleOrbit, BathRigInvertsWithItsFirstBendingModeOnly) {
  const auto& p = bath_board().plant;
  const mr::RotorModel rotor = mr::build_rotor_model(p.rotor);
  const amb::model::drop::FlexibleOrbit one(rotor, p.rotor, sensor_planes(p), aux_planes(p), 1, p.gravity_m_s2);
  ASSERT_EQ(one.bending_frequencies_hz().size(), 1u);
  EXPECT_NEAR(one.bending_frequencies_hz()[0], 368.0, 5.0);  // free-free, the FE rotor's first
  EXPECT_TRUE(one.usable());
  ASSERT_EQ(one.inverse_frequencies_hz().size(), 1u);
  EXPECT_GT(one.inverse_frequencies_hz()[0], one.bending_frequencies_hz()[0]);
  const amb::model::drop::FlexibleOrbit two(rotor, p.rotor, sensor_planes(p), aux_planes(p), 2, p.gravity_m_s2);
  EXPECT_FALSE(two.usable());
  EXPECT_THROW(amb::model::drop::FlexibleOrbit(rotor, p.rotor, sensor_planes(p), aux_planes(p), 0, p.gravity_m_s2),
               std::invalid_argument);
}

// The rotor's modal model (two rigid-body modes and the first bending mode per plane, the
// board's damping) driven by gravity and two impacts at the aux planes, integrated at 1 us
// and sampled at 10 kHz: rigid_part() returns the rigid-body part of the sensor readings to
// within 3 % of the bending it removes; the readings themselves are off by all of it.
TEST(FlexibleOrbit, RecoversTheRigidPartOfAModalSimulation) {
  const auto& p = bath_board().plant;
  const mr::RotorModel rotor = mr::build_rotor_model(p.rotor);
  const mr::ReducedRotor red = mr::reduce_rotor(rotor, p.rotor, 3);
  Eigen::Matrix<double, 2, 3> s, a;
  for (int i = 0; i < 2; ++i) {
    s.row(i) = mr::modal_interpolation(rotor, red, sensor_planes(p)[static_cast<size_t>(i)]);
    a.row(i) = mr::modal_interpolation(rotor, red, aux_planes(p)[static_cast<size_t>(i)]);
  }
  const Eigen::Vector3d grav = mr::modal_gravity_load(rotor, red, p.gravity_m_s2);
  // Half-sine impacts: bearing A in x (400 N, 0.8 ms from 3 ms), bearing B in y (600 N, 1 ms from 6 ms).
  const auto pulse = [](double t, double t0, double len, double peak) {
    return t >= t0 && t <= t0 + len ? peak * std::sin(M_PI * (t - t0) / len) : 0.0;
  };
  const double h = 1e-6, dt = 1e-4;
  const int per_sample = static_cast<int>(std::lround(dt / h)), samples = 300;
  std::array<Eigen::Vector3d, 2> q{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}, v = q;
  const auto accel = [&](int plane, double t, const Eigen::Vector3d& qq, const Eigen::Vector3d& vv) {
    Eigen::Vector2d f = Eigen::Vector2d::Zero();
    if (plane == 0) f(0) = pulse(t, 3e-3, 0.8e-3, 400.0);
    else f(1) = pulse(t, 6e-3, 1e-3, 600.0);
    Eigen::Vector3d acc = a.transpose() * f - red.damping.cwiseProduct(vv) - red.omega2.cwiseProduct(qq);
    if (plane == 1) acc += grav;
    return acc;
  };
  std::vector<std::array<double, 4>> readings, rigid_truth, aux_truth;
  double bending_max = 0.0;
  for (int k = 0; k < samples; ++k) {
    std::array<double, 4> r{}, rt{};
    for (int plane = 0; plane < 2; ++plane) {
      const Eigen::Vector2d y = s * q[static_cast<size_t>(plane)];
      const Eigen::Vector2d yr = s.leftCols(2) * q[static_cast<size_t>(plane)].head(2);
      r[static_cast<size_t>(plane)] = y(0);
      r[static_cast<size_t>(2 + plane)] = y(1);
      rt[static_cast<size_t>(plane)] = yr(0);
      rt[static_cast<size_t>(2 + plane)] = yr(1);
      bending_max = std::max(bending_max, (y - yr).cwiseAbs().maxCoeff());
    }
    std::array<double, 4> at{};
    for (int plane = 0; plane < 2; ++plane) {
      const Eigen::Vector2d ya = a * q[static_cast<size_t>(plane)];
      at[static_cast<size_t>(plane)] = ya(0);
      at[static_cast<size_t>(2 + plane)] = ya(1);
    }
    readings.push_back(r);
    rigid_truth.push_back(rt);
    aux_truth.push_back(at);
    for (int j = 0; j < per_sample; ++j) {
      const double t = k * dt + j * h;
      for (int plane = 0; plane < 2; ++plane) {
        auto& qq = q[static_cast<size_t>(plane)];
        auto& vv = v[static_cast<size_t>(plane)];
        const Eigen::Vector3d k1q = vv, k1v = accel(plane, t, qq, vv);
        const Eigen::Vector3d k2q = vv + 0.5 * h * k1v, k2v = accel(plane, t + 0.5 * h, qq + 0.5 * h * k1q, k2q);
        const Eigen::Vector3d k3q = vv + 0.5 * h * k2v, k3v = accel(plane, t + 0.5 * h, qq + 0.5 * h * k2q, k3q);
        const Eigen::Vector3d k4q = vv + h * k3v, k4v = accel(plane, t + h, qq + h * k3q, k4q);
        qq += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
        vv += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
      }
    }
  }
  ASSERT_GT(bending_max, 1e-7);  // the impacts bend the rotor by a material amount at the sensors
  const amb::model::drop::FlexibleOrbit flex(rotor, p.rotor, sensor_planes(p), aux_planes(p), 1, p.gravity_m_s2);
  ASSERT_TRUE(flex.usable());
  const auto rigid = flex.rigid_part(readings, dt);
  double err = 0.0;
  for (int k = 0; k < samples; ++k)
    for (size_t c = 0; c < 4; ++c) err = std::max(err, std::abs(rigid[static_cast<size_t>(k)][c] - rigid_truth[static_cast<size_t>(k)][c]));
  std::printf("bending at the sensors up to %.3f um; rigid part recovered to %.4f um\n", 1e6 * bending_max, 1e6 * err);
  EXPECT_LT(err, 0.03 * bending_max);

  // Where the rotor touches its aux bearings: aux_planes() against the modal truth there, and
  // the straight line through the two sensor planes (what a rigid-rotor view reads) against it.
  const auto aux = flex.aux_planes(readings, dt);
  const double za = sensor_planes(p)[0], zb = sensor_planes(p)[1];
  double aux_err = 0.0, line_err = 0.0;
  for (int k = 0; k < samples; ++k)
    for (size_t plane = 0; plane < 2; ++plane)
      for (size_t b = 0; b < 2; ++b) {
        const double s_b = (aux_planes(p)[b] - za) / (zb - za);
        const auto& r = readings[static_cast<size_t>(k)];
        const double line = r[plane] + s_b * (r[2 + plane] - r[plane]);
        const double truth = aux_truth[static_cast<size_t>(k)][2 * b + plane];
        aux_err = std::max(aux_err, std::abs(aux[static_cast<size_t>(k)][2 * b + plane] - truth));
        line_err = std::max(line_err, std::abs(line - truth));
      }
  std::printf("aux planes: straight-line view off by up to %.3f um, aux_planes() by %.4f um\n", 1e6 * line_err, 1e6 * aux_err);
  ASSERT_GT(line_err, 1e-7);
  EXPECT_LT(aux_err, 0.03 * line_err);
}

}  // namespace
