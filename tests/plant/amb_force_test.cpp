// The nonlinear AMB force law (seed 002 eq. 14) and its linearisation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "model/amb/amb_force.hpp"
#include "tests/plant/rig_fixture.hpp"

namespace amb::model::magnet {
namespace {

class AmbLaw : public ::testing::TestWithParam<const char*> {};

// Central finite differences of the nonlinear law at the centre give the board's ks and ki.
TEST_P(AmbLaw, LinearisationMatchesKsKiByFiniteDifferences) {
  const auto board = test::board_from_repo(GetParam());
  const AmbParams& p = board.plant.amb[0];
  const AxisLaw law = make_axis_law(p);
  const double dz = 1e-4 * p.gap_m, di = 1e-4 * law.bias_a;
  const double ks_fd = (axis_force_n(law, dz, 0.0) - axis_force_n(law, -dz, 0.0)) / (2.0 * dz);
  const double ki_fd = (axis_force_n(law, 0.0, di) - axis_force_n(law, 0.0, -di)) / (2.0 * di);
  std::printf("[ RESULT ] %s: ks board %.4g, finite difference %.6g N/m; ki board %.4g, finite difference %.6g N/A; i0 %.4g A\n",
              GetParam(), p.ks_n_per_m, ks_fd, p.ki_n_per_a, ki_fd, law.bias_a);
  EXPECT_NEAR(ks_fd, p.ks_n_per_m, 1e-6 * p.ks_n_per_m);
  EXPECT_NEAR(ki_fd, p.ki_n_per_a, 1e-6 * p.ki_n_per_a);
  // The analytic linearisation agrees away from the centre too.
  const double z = 0.3 * p.gap_m, i = 0.2 * law.bias_a;
  const Linearisation l = linearise(law, z, i);
  const double ks2 = (axis_force_n(law, z + dz, i) - axis_force_n(law, z - dz, i)) / (2.0 * dz);
  const double ki2 = (axis_force_n(law, z, i + di) - axis_force_n(law, z, i - di)) / (2.0 * di);
  if (std::abs(axis_force_n(law, z, i)) < 0.9 * law.max_coil_force_n) {
    EXPECT_NEAR(l.ks_n_per_m, ks2, 1e-5 * std::abs(ks2));
    EXPECT_NEAR(l.ki_n_per_a, ki2, 1e-5 * std::abs(ki2));
  }
  // The bias the plant uses agrees with the board's within the loader's tolerance.
  EXPECT_NEAR(law.bias_a, p.bias_current_a, 0.25 * p.bias_current_a);
}

// The set-point feed-forward current cancels the bias pull anywhere inside the gap (the law is
// far from linear there: at half the gap the pull is 1.8x ks z); outside it, it is held.
TEST_P(AmbLaw, ZeroForceCurrentCancelsTheBiasPull) {
  const auto board = test::board_from_repo(GetParam());
  const AxisLaw law = make_axis_law(board.plant.amb[0]);
  int checked = 0;
  for (const double r : {-0.6, -0.5, -0.25, -0.05, 0.0, 0.05, 0.25, 0.5, 0.6}) {
    const double z = r * law.gap_m;
    const double ic = zero_force_current_a(law, z);
    if (std::max(law.k_n_m2_per_a2 * (law.bias_a + std::abs(ic)) * (law.bias_a + std::abs(ic)) /
                     ((law.gap_m - std::abs(z)) * (law.gap_m - std::abs(z))),
                 0.0) >= law.max_coil_force_n)
      continue;  // a saturated coil: no current cancels it exactly
    EXPECT_NEAR(axis_force_n(law, z, ic), 0.0, 1e-9 * std::abs(axis_force_n(law, z, 0.0)) + 1e-12) << "z/g0 " << r;
    EXPECT_LE(ic * z, 0.0);  // pulls away from the nearer pole
    ++checked;
  }
  EXPECT_GE(checked, 5);
  EXPECT_EQ(zero_force_current_a(law, 10.0 * law.gap_m), zero_force_current_a(law, law.gap_m));  // held at the gap
}

// Opposed coils: F(-z, -i) = -F(z, i); zero at the centre without control current.
TEST_P(AmbLaw, ForceIsAntisymmetric) {
  const auto board = test::board_from_repo(GetParam());
  const AxisLaw law = make_axis_law(board.plant.amb[1]);
  EXPECT_EQ(axis_force_n(law, 0.0, 0.0), 0.0);
  for (double z : {0.0, 1e-5, 2e-4, -3e-4})
    for (double i : {0.0, 0.3, -1.1}) EXPECT_NEAR(axis_force_n(law, z, i), -axis_force_n(law, -z, -i), 1e-9) << z << " " << i;
}

// Full control current at the rotor's touchdown position saturates at the flux limit and
// never exceeds it; the force is monotonic in the current.
TEST_P(AmbLaw, Saturates) {
  const auto board = test::board_from_repo(GetParam());
  const AmbParams& p = board.plant.amb[0];
  const AxisLaw law = make_axis_law(p);
  double prev = -1e300;
  for (double i = -2.0 * law.bias_a; i <= 2.0 * law.bias_a; i += 0.01 * law.bias_a) {
    const double f = axis_force_n(law, 0.5 * p.gap_m, i);
    EXPECT_LE(std::abs(f), p.max_force_n + 1e-9);
    EXPECT_GE(f, prev - 1e-9);
    prev = f;
  }
  EXPECT_NEAR(axis_force_n(law, 0.5 * p.gap_m, 2.0 * law.bias_a), p.max_force_n, 1e-9);
  EXPECT_NEAR(axis_force_n(law, -0.5 * p.gap_m, -2.0 * law.bias_a), -p.max_force_n, 1e-9);
  std::printf("[ RESULT ] %s: F(z=0, ic=i0) = %.0f N (ki*i0 = %.0f N), capped at %.0f N\n", GetParam(),
              axis_force_n(law, 0.0, law.bias_a), p.ki_n_per_a * law.bias_a, p.max_force_n);
}

INSTANTIATE_TEST_SUITE_P(Boards, AmbLaw, ::testing::Values("bath-amb-rig", "unicamp-amb-rig"));

TEST(AmbAxes, DirectionsFollowTheVerticalAngleConvention) {
  const auto up = axis_direction(0.0), right = axis_direction(90.0), a45 = axis_direction(45.0);
  EXPECT_NEAR(up[0], 0.0, 1e-15);
  EXPECT_NEAR(up[1], 1.0, 1e-15);
  EXPECT_NEAR(right[0], 1.0, 1e-15);
  EXPECT_NEAR(a45[0], std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(a45[1], std::sqrt(0.5), 1e-15);
}

}  // namespace
}  // namespace amb::model::magnet
