// Ball-size variation of the contact law (hertz_contact.hpp, BallSizeVariation): the larger ball
// carries more load, the support force then repeats once per cage revolution instead of once per
// ball pass, zero excess is the healthy law bit for bit, and bad parameters are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "model/bearing/catalogue.hpp"
#include "model/bearing/hertz_contact.hpp"

namespace mb = amb::model::bearing;

namespace {
mb::ContactLawParams params(double excess_m) {
  mb::ContactLawParams cp;
  cp.geometry = *mb::find_bearing("6205");
  cp.hertz_constant_n_per_m1p5 = 1e10;
  cp.radial_clearance_m = 5e-6;
  cp.ball_size.excess_diameter_m = excess_m;
  cp.ball_size.ball_index = 0;
  return cp;
}
}  // namespace

TEST(BallSizeVariation, OversizedBallBreaksTheBallPassPeriod) {
  mb::HertzContactLaw equal, oversized;
  ASSERT_TRUE(equal.configure(params(0.0)));
  ASSERT_TRUE(oversized.configure(params(1e-6)));
  const int z = 9;
  const double dy = 15e-6, pitch = 2.0 * M_PI / z;
  // Ball 0 at the bottom of the load zone (+y, cage angle pi/2) and one ball pass later.
  const double a0 = M_PI / 2;
  const auto e0 = equal.force_at_cage_angle(0.0, dy, a0, 0.0), e1 = equal.force_at_cage_angle(0.0, dy, a0 + pitch, 0.0);
  const auto o0 = oversized.force_at_cage_angle(0.0, dy, a0, 0.0), o1 = oversized.force_at_cage_angle(0.0, dy, a0 + pitch, 0.0);
  // Equal balls: the pattern repeats every ball pass (to rounding).
  EXPECT_NEAR(e0.fy_n, e1.fy_n, 1e-9 * std::abs(e0.fy_n));
  // Oversized ball 0 in the load zone: more force than with equal balls, and by the Hertz law:
  // ball 0's deflection 10 um -> 11 um adds k (11^1.5 - 10^1.5) um^1.5.
  const double extra = 1e10 * (std::pow(11e-6, 1.5) - std::pow(10e-6, 1.5));
  EXPECT_NEAR(o0.fy_n - e0.fy_n, extra, 1e-6 * extra);
  // One ball pass later ball 0 has left the bottom: the force differs from a0's.
  EXPECT_GT(std::abs(o0.fy_n - o1.fy_n), 0.1 * extra);
  // A full cage revolution later it is back.
  const auto o9 = oversized.force_at_cage_angle(0.0, dy, a0 + z * pitch, 0.0);
  EXPECT_NEAR(o9.fy_n, o0.fy_n, 1e-9 * std::abs(o0.fy_n));
}

TEST(BallSizeVariation, ZeroExcessIsTheHealthyLaw) {
  mb::ContactLawParams plain = params(0.0);
  plain.ball_size = {};
  mb::HertzContactLaw a, b;
  ASSERT_TRUE(a.configure(plain));
  ASSERT_TRUE(b.configure(params(0.0)));
  for (double ang = 0.0; ang < 6.3; ang += 0.37) {
    const auto fa = a.force_at_cage_angle(3e-6, 12e-6, ang, 0.0), fb = b.force_at_cage_angle(3e-6, 12e-6, ang, 0.0);
    EXPECT_EQ(fa.fx_n, fb.fx_n);
    EXPECT_EQ(fa.fy_n, fb.fy_n);
  }
}

TEST(BallSizeVariation, BadParametersAreRefused) {
  mb::HertzContactLaw law;
  EXPECT_FALSE(law.configure(params(-1e-7)));
  EXPECT_FALSE(law.configure(params(std::nan(""))));
  auto p = params(1e-6);
  p.ball_size.ball_index = 9;  // the 6205 has balls 0..8
  EXPECT_FALSE(law.configure(p));
  p.ball_size.ball_index = -1;
  EXPECT_FALSE(law.configure(p));
}
