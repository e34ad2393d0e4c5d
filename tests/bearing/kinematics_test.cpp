// Seed checks of the rolling-bearing kinematics and the catalogue.
#include <gtest/gtest.h>

#include "model/bearing/catalogue.hpp"
#include "model/bearing/geometry.hpp"

namespace mb = amb::model::bearing;

TEST(BearingKinematics, Seed001CageAndOuterRaceAt2000Rpm) {
  const auto g = mb::find_bearing("SKF 6200");
  ASSERT_TRUE(g);
  // Seed 001 eq. 14: 762 rpm cage at 2000 rpm; eq. 15: -3963.6 rpm roller; eq. 16: 101.6 Hz.
  EXPECT_NEAR(mb::cage_speed(*g, 2000.0, 0.0), 762.0, 0.5);
  EXPECT_NEAR(mb::ball_spin_speed(*g, 2000.0, 0.0), -3963.6, 0.5);
  EXPECT_NEAR(mb::defect_frequencies(*g, 2000.0 / 60.0).bpfo_hz, 101.6, 0.05);
  EXPECT_NEAR(mb::defect_frequencies(*g, 2000.0 / 60.0).ftf_hz * 60.0, 762.0, 0.5);
}

TEST(BearingKinematics, Seed003BpfiAndShaftAt5000Rpm) {
  const auto g = mb::find_bearing("6206");
  ASSERT_TRUE(g);
  const auto f = mb::defect_frequencies(*g, 5000.0 / 60.0);
  EXPECT_NEAR(f.shaft_hz, 83.3, 0.05);  // "fr, 83 Hz"
  EXPECT_NEAR(f.bpfi_hz, 450.0, 5.0);   // "BPFI, 450 Hz" (452.6 from the geometry)
}

TEST(BearingKinematics, CwruPublishedOrdersFor6205) {
  const auto g = mb::find_bearing("SKF 6205-2RS JEM");
  ASSERT_TRUE(g);
  const auto o = mb::defect_orders(*g);
  EXPECT_NEAR(o.bpfi, 5.4152, 5e-4);
  EXPECT_NEAR(o.bpfo, 3.5848, 5e-4);
  EXPECT_NEAR(o.ftf, 0.39828, 5e-5);
  EXPECT_NEAR(o.bsf, 2.357, 5e-4);
}

TEST(BearingCatalogue, HasRequiredBearingsAndRejectsUnknown) {
  for (const char* n : {"SKF 6205", "SKF 6203", "SKF 6206", "SKF 6200", "6205", "skf6203"}) {
    const auto g = mb::find_bearing(n);
    ASSERT_TRUE(g) << n;
    EXPECT_TRUE(g->valid()) << n;
  }
  EXPECT_FALSE(mb::find_bearing("SKF 9999"));
  EXPECT_FALSE(mb::find_bearing(""));
}

// The fan-end 6203's orders against the CWRU README's published values (data/measured).
TEST(BearingKinematics, CwruPublishedOrdersFor6203) {
  const auto o = mb::defect_orders(*mb::find_bearing("6203"));
  EXPECT_NEAR(o.bpfi, 4.9469, 5e-4);
  EXPECT_NEAR(o.bpfo, 3.0530, 5e-4);
  // The README's FTF 0.3817 is not its own BPFO / Z = 0.38163 (kinematics: BPFO = Z FTF exactly),
  // so FTF is checked to the published BPFO's consistency, 1e-4.
  EXPECT_NEAR(o.ftf, 0.3817, 1e-4);
  EXPECT_NEAR(o.bsf, 1.9937, 5e-4);
}

TEST(BearingKinematics, OrdersSatisfyIdentities) {
  for (const auto& g : mb::bearing_catalogue()) {
    const auto o = mb::defect_orders(g);
    EXPECT_NEAR(o.bpfo + o.bpfi, g.ball_count, 1e-12) << g.name;
    EXPECT_NEAR(o.bpfo, g.ball_count * o.ftf, 1e-12) << g.name;
  }
}
