// The 4-DOF and 8-DOF models: contact law, step cost, defect lines in the envelope spectrum.
#include <gtest/gtest.h>

#include <cmath>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "tests/bearing/model_records.hpp"
#include "model/bearing/catalogue.hpp"
#include "model/bearing/hertz_4dof.hpp"
#include "model/bearing/rotor_8dof.hpp"

namespace mb = amb::model::bearing;
namespace hb = amb::host::bearing;

namespace {
using amb::test::bearing::with_defect;
constexpr double k_fs_hz = 20000.0;
constexpr double k_speed_hz = 5000.0 / 60.0;
}  // namespace

TEST(HertzContact, ClearanceAndThreeHalvesLaw) {
  mb::ContactLawParams cp;
  cp.geometry = *mb::find_bearing("6206");
  cp.hertz_constant_n_per_m1p5 = 1e10;
  cp.radial_clearance_m = 5e-6;
  mb::HertzContactLaw law;
  ASSERT_TRUE(law.configure(cp));
  EXPECT_EQ(law.force(4e-6, 0.0, 0.0).balls_loaded, 0);  // inside the clearance
  // Ball 0 at angle 0 when the cage angle is 0: only it is loaded for a small x push.
  const auto f = law.force(5e-6 + 1e-6, 0.0, 0.0);
  EXPECT_EQ(f.balls_loaded, 1);
  EXPECT_NEAR(f.fx_n, 1e10 * std::pow(1e-6, 1.5), 1e-9);
  cp.hertz_constant_n_per_m1p5 = -1;
  EXPECT_FALSE(law.configure(cp));
}

TEST(HertzContact, OuterGrooveUnloadsBallInside) {
  mb::ContactLawParams cp;
  cp.geometry = *mb::find_bearing("6206");
  cp.hertz_constant_n_per_m1p5 = 1e10;
  cp.defect.location = mb::DefectLocation::outer_race;
  cp.defect.width_m = 0.5e-3;
  cp.defect.depth_m = 0.3e-3;
  mb::HertzContactLaw law;
  ASSERT_TRUE(law.configure(cp));
  // Capped by the ball geometry (seed 001 eq. 6): r - sqrt(r^2 - (L/2)^2) ~ 6.6 um.
  EXPECT_NEAR(law.defect_depth_m(), 6.57e-6, 0.05e-6);
  // Ball 0 sits in the groove at 0 rad: it loses exactly its own Hertz force k (5 um)^1.5.
  mb::ContactLawParams healthy_p = cp;
  healthy_p.defect = {};
  mb::HertzContactLaw healthy;
  ASSERT_TRUE(healthy.configure(healthy_p));
  const auto fd = law.force(5e-6, 0, 0);
  const auto fh = healthy.force(5e-6, 0, 0);
  EXPECT_EQ(fd.balls_loaded + 1, fh.balls_loaded);
  EXPECT_NEAR(fh.fx_n - fd.fx_n, 1e10 * std::pow(5e-6, 1.5), 1e-6);
  // Once the cage has moved the ball off the groove, the two laws agree again.
  const double shaft = 0.3 / law.cage_ratio();
  EXPECT_NEAR(law.force(5e-6, 0, shaft).fx_n, healthy.force(5e-6, 0, shaft).fx_n, 1e-9);
}

TEST(Hertz4Dof, DeterministicAndSized) {
  const auto p = with_defect(mb::DefectLocation::outer_race);
  auto speed = [](double) { return k_speed_hz; };
  const auto a = mb::simulate_housing_acceleration(p, speed, k_fs_hz, 0.1, 0.01, 42);
  const auto b = mb::simulate_housing_acceleration(p, speed, k_fs_hz, 0.1, 0.01, 42);
  ASSERT_EQ(a.size(), 2000u);
  EXPECT_EQ(a, b);
  for (double v : a) ASSERT_TRUE(std::isfinite(v));
  mb::Hertz4DofParams bad = p;
  bad.shaft_mass_kg = 0;
  EXPECT_THROW(mb::simulate_housing_acceleration(bad, speed, k_fs_hz, 0.1, 0, 1), std::invalid_argument);
}

TEST(Hertz4Dof, StepDoesNotAllocate) {
  mb::Hertz4DofModel m;
  ASSERT_TRUE(m.configure(with_defect(mb::DefectLocation::inner_race)));
  mb::Hertz4DofState y = m.initial_state();
  Eigen::internal::set_is_malloc_allowed(false);
  double acc = 0;
  for (int i = 0; i < 1000; ++i) {
    const mb::Hertz4DofState d = m.derivative(y, k_speed_hz);
    y += 1e-6 * d;
    acc += m.sensor_acceleration(d);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(std::isfinite(acc));
}

TEST(Hertz4Dof, StepRuleResolvesDefectTransit) {
  mb::Hertz4DofModel m;
  ASSERT_TRUE(m.configure(with_defect(mb::DefectLocation::outer_race)));
  const double h = m.choose_step_s(k_speed_hz, k_fs_hz);
  const double transit = 2 * m.contact().defect_half_angle_rad() / (2 * M_PI * k_speed_hz * m.contact().cage_ratio());
  EXPECT_LE(h, transit / 4 + 1e-12);
  EXPECT_NEAR(std::fmod(1.0 / k_fs_hz / h, 1.0), 0.0, 1e-6);
}

// The simulated envelope spectrum shows the defect line at its kinematic frequency.
TEST(Hertz4Dof, EnvelopeShowsOuterAndInnerRaceLines) {
  auto speed = [](double) { return k_speed_hz; };
  const auto g = *mb::find_bearing("6206");
  const auto kin = mb::defect_frequencies(g, k_speed_hz);
  const hb::BearingCheckOptions o;
  for (auto loc : {mb::DefectLocation::outer_race, mb::DefectLocation::inner_race}) {
    const auto x = mb::simulate_housing_acceleration(with_defect(loc), speed, k_fs_hz, 1.0, 0.05, 3);
    const auto healthy =
        mb::simulate_housing_acceleration(with_defect(mb::DefectLocation::none), speed, k_fs_hz, 1.0, 0.05, 3);
    const double f = loc == mb::DefectLocation::outer_race ? kin.bpfo_hz : kin.bpfi_hz;
    hb::BandAnalyser a(x, k_fs_hz), ah(healthy, k_fs_hz);
    const auto band = a.select_band({});
    const auto s = a.envelope_spectrum(band);
    const auto sh = ah.envelope_spectrum(band);
    const auto line = hb::find_line(s, f, 0.005, o);
    ASSERT_TRUE(line.stands_out()) << "defect " << static_cast<int>(loc) << " ratio " << line.ratio;
    EXPECT_NEAR(*line.found_hz, f, 0.005 * f);
    // The defect, not the healthy bearing's varying compliance, makes the line.
    EXPECT_GT(s.at(*line.found_hz), 3.0 * sh.at(*line.found_hz)) << static_cast<int>(loc);
  }
}

TEST(Hertz4Dof, FollowsTimeVaryingSpeed) {
  // Run-up 40 -> 90 Hz over 1 s: the second half's BPFO line sits at the mean speed of that half.
  auto p = with_defect(mb::DefectLocation::outer_race);
  auto ramp = [](double t) { return 40.0 + 50.0 * t; };
  const auto x = mb::simulate_housing_acceleration(p, ramp, k_fs_hz, 1.0, 0.0, 1);
  const std::vector<double> half(x.begin() + 15000, x.end());  // t in [0.75, 1.0): 77.5..90 Hz
  hb::BandAnalyser a(half, k_fs_hz);
  const auto s = a.envelope_spectrum(a.select_band({}));
  const double bpfo = mb::defect_orders(p.bearing).bpfo * 83.75;
  hb::BearingCheckOptions o;
  const auto line = hb::find_line(s, bpfo, 0.1, o);  // smeared over +-7.5 %
  ASSERT_TRUE(line.stands_out());
  EXPECT_NEAR(line.peak_hz, bpfo, 0.08 * bpfo);
}

TEST(Rotor8Dof, SharesContactLawAndSettlesOnBearings) {
  mb::Rotor8DofParams p;
  mb::ContactLawParams cp;
  cp.geometry = *mb::find_bearing("6200");
  cp.hertz_constant_n_per_m1p5 = mb::nominal_hertz_constant(cp.geometry);
  cp.radial_clearance_m = 5e-6;
  p.bearing_a = cp;
  cp.defect.location = mb::DefectLocation::outer_race;
  cp.defect.profile = mb::DefectProfile::cosine;  // seed 001 eq. 5
  cp.defect.width_m = 0.5e-3;
  cp.defect.depth_m = 1e-3;
  cp.defect.angle_rad = -M_PI / 2;  // load zone under gravity
  p.bearing_b = cp;
  mb::Rotor8DofModel m;
  ASSERT_TRUE(m.configure(p));
  mb::Rotor8DofState y = mb::Rotor8DofState::Zero();
  std::function<double(double)> speed = [](double) { return 2000.0 / 60.0; };
  double t = 0;
  const int n = static_cast<int>(0.3 / p.step_s);
  for (int i = 0; i < n; ++i, t += p.step_s) m.step(y, t, speed);
  // Static check: the two bearing reactions carry the rotor weight.
  const double weight = (p.m1_kg + p.m2_kg + p.m3_kg + p.m4_kg) * p.gravity_m_per_s2;
  double fy = 0;
  const int avg = static_cast<int>(0.05 / p.step_s);
  for (int i = 0; i < avg; ++i, t += p.step_s) {
    m.step(y, t, speed);
    fy += m.bearing_reaction(y, 0).fy_n + m.bearing_reaction(y, 1).fy_n;
  }
  EXPECT_NEAR(fy / avg, weight, 0.05 * weight);
  EXPECT_LT(y[1], -5e-6);  // rotor sits below centre by more than the clearance
}
