// bearing-check on a model-made ball-fault record: the cage family is the ball's FTF modulation
// (BearingCheckOptions::cage_as_ball_modulation). One record of BallRecords
// (model_validation.cpp), the 4-DOF 6206 with a 0.5 mm spot at 45 Hz.
#include <gtest/gtest.h>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "tests/bearing/model_records.hpp"

namespace hb = amb::host::bearing;
namespace mb = amb::model::bearing;
namespace tb = amb::test::bearing;

TEST(BallCheck, CageLinesAreTheBallsModulationNotAVerdict) {
  tb::RecordSpec s;
  s.model = "4dof";
  s.bearing = "6206";
  s.defect = mb::DefectLocation::ball;
  s.width_mm = 0.5;
  s.speed_hz = 45.0;
  s.fs_hz = 12000.0;
  s.duration_s = 10.0;
  s.noise_rel = 0.5;
  s.path = 0;
  s.seed = 5005;
  const auto x = tb::make_record(s);
  ASSERT_FALSE(x.empty());
  const auto g = *mb::find_bearing("6206");
  const auto r = hb::check_bearing(x, s.fs_hz, s.speed_hz * 1.004, g);
  EXPECT_EQ(r.verdict, "ball") << r.reason;
  EXPECT_TRUE(r.family("ftf").detected);
  EXPECT_NE(r.family("ftf").reason.find("cage modulation"), std::string::npos) << r.family("ftf").reason;
  // Without the rule the stronger cage family takes the verdict: "unclear" (only the cage; with
  // cage_modulation_as_ball off too, which would otherwise read the cage alone as a ball fault).
  hb::BearingCheckOptions o;
  o.cage_as_ball_modulation = false;
  o.cage_modulation_as_ball = false;
  const auto r0 = hb::check_bearing(x, s.fs_hz, s.speed_hz * 1.004, g, o);
  EXPECT_EQ(r0.verdict, "unclear") << r0.reason;
  EXPECT_TRUE(r0.family("ball").detected);
  // The healthy bearing at the same settings stays healthy.
  s.defect = mb::DefectLocation::none;
  const auto h = hb::check_bearing(tb::make_record(s), s.fs_hz, s.speed_hz * 1.004, g);
  EXPECT_EQ(h.verdict, "healthy") << h.reason;
}
