// Board-side background bearing task.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "firmware/bearing/bearing_task.hpp"
#include "model/bearing/catalogue.hpp"

namespace mb = amb::model::bearing;

namespace {
amb::fw::BearingTaskConfig config() {
  amb::fw::BearingTaskConfig c;
  c.bearing = *mb::find_bearing("6205");
  c.aux_radial_clearance_m = 0.7e-3;            // seed 002 touchdown clearance
  c.aux_contact_constant_n_per_m1p5 = 5e9;
  c.aux_dynamic_load_rating_n = 14000;
  c.aux_spin_speed_hz = 45;
  return c;
}
}  // namespace

TEST(BearingTask, DefectFrequenciesAtTrackedSpeed) {
  amb::fw::BearingTask t;
  ASSERT_TRUE(t.configure(config()));
  const auto u = t.update_speed(29.95);
  ASSERT_TRUE(u.valid);
  EXPECT_NEAR(u.bpfi_hz / 29.95, 5.4152, 5e-4);
  EXPECT_FALSE(t.update_speed(-3.0).valid);
  EXPECT_FALSE(t.update_speed(NAN).valid);
  EXPECT_EQ(t.counters().rejected_speeds, 2u);
}

TEST(BearingTask, StiffnessGrowsWithLoadAndEta) {
  amb::fw::BearingTask t;
  ASSERT_TRUE(t.configure(config()));
  const auto a = t.update_stiffness(500.0);
  const auto b = t.update_stiffness(5000.0);
  ASSERT_TRUE(a.valid && b.valid);
  EXPECT_GT(b.stiffness_n_per_m, a.stiffness_n_per_m);  // Hertz: stiffening
  EXPECT_GT(a.stiffness_n_per_m, 1e6);
  ASSERT_TRUE(t.set_stiffness_scale(2.0));
  EXPECT_GT(t.update_stiffness(500.0).stiffness_n_per_m, a.stiffness_n_per_m);
  EXPECT_FALSE(t.set_stiffness_scale(0.0));
  EXPECT_FALSE(t.update_stiffness(-1.0).valid);
}

TEST(BearingTask, DropLoadBinsHertzForceByAngle) {
  amb::fw::BearingTask t;
  ASSERT_TRUE(t.configure(config()));
  // Rotor pressed 10 um into the clearance at 270 deg for 100 samples, free elsewhere.
  const double c = 0.7e-3, dt = 1e-4;
  std::vector<double> x(300, 0.0), y(300, 0.0);
  for (int i = 100; i < 200; ++i) y[static_cast<size_t>(i)] = -(c + 10e-6);
  amb::fw::DropLoadEstimate e;
  t.estimate_drop_load(x, y, dt, e);
  ASSERT_TRUE(e.valid);
  const double f = 5e9 * std::pow(10e-6, 1.5);
  EXPECT_EQ(e.samples_in_contact, 100u);
  EXPECT_NEAR(e.peak_force_n, f, 1e-6 * f);
  EXPECT_NEAR(e.peak_angle_deg, 270.0, 1e-9);
  EXPECT_NEAR(e.impulse_n_s[270], f * 100 * dt, 1e-9);
  EXPECT_NEAR(e.damage_total_n3_s, f * f * f * 100 * dt, 1e-6 * f * f * f * 100 * dt);
  EXPECT_NEAR(e.miner_fraction, e.damage_total_n3_s / std::pow(14000.0, 3) * 45 / 1e6, 1e-18);
  // Mismatched lengths are refused and counted.
  t.estimate_drop_load(std::span<const double>(x).first(10), y, dt, e);
  EXPECT_FALSE(e.valid);
  EXPECT_EQ(t.counters().rejected_drops, 1u);
}
