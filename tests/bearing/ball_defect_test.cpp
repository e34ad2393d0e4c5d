// The ball (rolling-element) spot defect of the contact law (hertz_contact.hpp) in both models:
// the spot ball unloaded at each race face, the depth caps, zero depth = healthy bit for bit,
// and, in a clean 4-DOF record, impacts at 2 x BSF modulated at the cage frequency FTF.
// The envelope spectrum here is computed directly (squared high-passed signal, Hann-windowed
// DFT), not with bearing-check's chain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "model/bearing/catalogue.hpp"
#include "model/bearing/hertz_4dof.hpp"
#include "model/bearing/rotor_8dof.hpp"

namespace mb = amb::model::bearing;

namespace {

mb::ContactLawParams law_params(const char* bearing) {
  mb::ContactLawParams cp;
  cp.geometry = *mb::find_bearing(bearing);
  cp.hertz_constant_n_per_m1p5 = 1e10;
  cp.radial_clearance_m = 0.0;
  return cp;
}

double sagitta(double radius_m, double half_width_m) {
  return radius_m - std::sqrt(radius_m * radius_m - half_width_m * half_width_m);
}

// Amplitude of the squared envelope's spectrum at f_hz: DFT (Hann) of the squared first
// difference (the impacts' high-frequency ringing; the first difference removes the slow
// structural response), its mean removed.
class DirectEnvelope {
 public:
  DirectEnvelope(const std::vector<double>& x, double fs_hz) : fs_hz_(fs_hz) {
    y_.resize(x.size() - 1);
    double mean = 0;
    for (size_t i = 1; i < x.size(); ++i) {
      const double d = x[i] - x[i - 1];
      y_[i - 1] = d * d;
      mean += d * d;
    }
    mean /= static_cast<double>(y_.size());
    const double n = static_cast<double>(y_.size());
    for (size_t i = 0; i < y_.size(); ++i)
      y_[i] = (y_[i] - mean) * (0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / n));
  }
  double bin_hz() const { return fs_hz_ / static_cast<double>(y_.size()); }
  double at(double f_hz) const {
    const std::complex<double> step = std::polar(1.0, -2.0 * M_PI * f_hz / fs_hz_);
    std::complex<double> ph = 1.0, acc = 0.0;
    for (size_t i = 0; i < y_.size(); ++i) {
      acc += y_[i] * ph;
      ph *= step;
      if ((i & 1023) == 1023) ph /= std::abs(ph);
    }
    return std::abs(acc);
  }
  // Largest amplitude within +-1 bin of f_hz (quarter-bin grid) and its frequency.
  std::pair<double, double> peak(double f_hz) const {
    std::pair<double, double> best{0.0, f_hz};
    for (int k = -4; k <= 4; ++k) {
      const double f = f_hz + 0.25 * k * bin_hz();
      const double a = at(f);
      if (a > best.first) best = {a, f};
    }
    return best;
  }
  // Median amplitude over f_hz +- 6 Hz, half-bin grid, the +-2 bins round f_hz left out.
  double floor(double f_hz) const {
    std::vector<double> v;
    for (double f = f_hz - 6.0; f <= f_hz + 6.0; f += 0.5 * bin_hz())
      if (std::abs(f - f_hz) > 2.0 * bin_hz()) v.push_back(at(f));
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
  }

 private:
  double fs_hz_;
  std::vector<double> y_;
};

mb::Hertz4DofParams ball_spot_6205(double width_m, double depth_m) {
  mb::Hertz4DofParams p;
  p.bearing = *mb::find_bearing("6205");
  p.defect.location = mb::DefectLocation::ball;
  p.defect.width_m = width_m;
  p.defect.depth_m = depth_m;
  p.defect.ball_index = 3;
  p.defect.angle_rad = 0.7;
  return p;
}

}  // namespace

TEST(BallSpot, UnloadsTheSpotBallFacingEitherRaceAndNowhereElse) {
  auto cp = law_params("6205");
  cp.defect.location = mb::DefectLocation::ball;
  cp.defect.width_m = 0.5e-3;
  cp.defect.depth_m = 0.3e-3;
  cp.defect.ball_index = 0;
  mb::HertzContactLaw law, healthy;
  auto hp = cp;
  hp.defect = {};
  ASSERT_TRUE(healthy.configure(hp));
  ASSERT_TRUE(law.configure(cp));
  // Caps: the race bridges the pit (ball sagitta -/+ race sagitta over L/2).
  const double r = 0.5 * cp.geometry.ball_diameter_m, h = 0.25e-3;
  const double cap_out = sagitta(r, h) - sagitta(cp.geometry.outer_raceway_radius_m(), h);
  const double cap_in = sagitta(r, h) + sagitta(cp.geometry.inner_raceway_radius_m(), h);
  EXPECT_NEAR(law.ball_spot_depth_outer_m(), cap_out, 1e-12);
  EXPECT_NEAR(law.ball_spot_depth_inner_m(), cap_in, 1e-12);
  EXPECT_GT(cap_in, cap_out);
  EXPECT_NEAR(law.spin_ratio(), mb::defect_orders(cp.geometry).bsf, 1e-12);
  // Ball 0 at cage angle 0 pushed by 2 um along x (cage angle given: the spin follows the shaft).
  const double push = 2e-6, q0 = 1e10 * std::pow(push, 1.5);
  for (double face : {0.0, M_PI}) {  // spot towards the outer race, then the inner race
    cp.defect.angle_rad = face;
    ASSERT_TRUE(law.configure(cp));
    const auto fd = law.force_at_cage_angle(push, 0, 0.0, 0.0);
    const auto fh = healthy.force_at_cage_angle(push, 0, 0.0, 0.0);
    EXPECT_EQ(fd.balls_loaded + 1, fh.balls_loaded) << face;
    EXPECT_NEAR(fh.fx_n - fd.fx_n, q0, 1e-9 * q0) << face;
  }
  // A deeper push than the cap: the ball keeps push - cap of deflection at the inner face.
  cp.defect.angle_rad = M_PI;
  ASSERT_TRUE(law.configure(cp));
  const double deep = cap_in + 1e-6;
  const auto fd = law.force_at_cage_angle(deep, 0, 0.0, 0.0), fh = healthy.force_at_cage_angle(deep, 0, 0.0, 0.0);
  EXPECT_NEAR(fh.fx_n - fd.fx_n, 1e10 * (std::pow(deep, 1.5) - std::pow(deep - cap_in, 1.5)), 1e-6);
  // Spot turned a quarter away from both races: the law is the healthy one.
  cp.defect.angle_rad = M_PI / 2;
  ASSERT_TRUE(law.configure(cp));
  EXPECT_EQ(law.force_at_cage_angle(push, 0, 0.0, 0.0).fx_n, healthy.force_at_cage_angle(push, 0, 0.0, 0.0).fx_n);
  // The spin follows the shaft angle: after 1/(2 BSF) shaft revolution the spot faces the
  // other race (from the outer face at angle 0 to the inner face).
  cp.defect.angle_rad = 0.0;
  ASSERT_TRUE(law.configure(cp));
  const double half_spin_shaft_rad = M_PI / law.spin_ratio();
  EXPECT_NEAR(law.force_at_cage_angle(push, 0, 0.0, half_spin_shaft_rad).fx_n,
              law.force_at_cage_angle(push, 0, 0.0, 0.0).fx_n, 1e-12);
  EXPECT_EQ(law.force_at_cage_angle(push, 0, 0.0, 0.5 * half_spin_shaft_rad).fx_n,
            healthy.force_at_cage_angle(push, 0, 0.0, 0.0).fx_n);
  // Bad ball index refused.
  cp.defect.ball_index = cp.geometry.ball_count;
  EXPECT_FALSE(law.configure(cp));
  cp.defect.ball_index = -1;
  EXPECT_FALSE(law.configure(cp));
}

TEST(BallSpot, StepRuleResolvesTheSpotTransit) {
  mb::Hertz4DofModel m;
  ASSERT_TRUE(m.configure(ball_spot_6205(0.2e-3, 0.1e-3)));
  const double speed_hz = 60.0, fs_hz = 12000.0;
  const double h = m.choose_step_s(speed_hz, fs_hz);
  const double transit = 2 * m.contact().defect_half_angle_rad() / (2 * M_PI * speed_hz * m.contact().spin_ratio());
  EXPECT_LE(h, transit / 4 + 1e-15);
  EXPECT_NEAR(std::fmod(1.0 / fs_hz / h, 1.0), 0.0, 1e-6);
}

TEST(BallSpot, ZeroDepthIsTheHealthyModelBitForBit) {
  auto speed = [](double t) { return 30.0 + 2.0 * t; };
  mb::Hertz4DofParams healthy;
  healthy.bearing = *mb::find_bearing("6205");
  const auto a = mb::simulate_housing_acceleration(healthy, speed, 12000.0, 0.3, 0.01, 7);
  // A narrow spot, whose transit would bound the step if it had depth (so the step rule is
  // part of what is compared).
  mb::Hertz4DofModel deep, flat, none;
  ASSERT_TRUE(deep.configure(ball_spot_6205(0.1e-3, 0.05e-3)));
  ASSERT_TRUE(flat.configure(ball_spot_6205(0.1e-3, 0.0)));
  ASSERT_TRUE(none.configure(healthy));
  ASSERT_LT(deep.choose_step_s(31.0, 12000.0), none.choose_step_s(31.0, 12000.0));
  EXPECT_EQ(flat.choose_step_s(31.0, 12000.0), none.choose_step_s(31.0, 12000.0));
  const auto b = mb::simulate_housing_acceleration(ball_spot_6205(0.1e-3, 0.0), speed, 12000.0, 0.3, 0.01, 7);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "a zero-depth ball spot changed the 4-DOF record";
  // 8-DOF (fixed step): same.
  mb::Rotor8DofParams p8;
  mb::ContactLawParams cp = law_params("6200");
  cp.hertz_constant_n_per_m1p5 = mb::nominal_hertz_constant(cp.geometry);
  cp.radial_clearance_m = 5e-6;
  p8.bearing_a = cp;
  p8.bearing_b = cp;
  mb::Rotor8DofParams q8 = p8;
  q8.bearing_b.defect.location = mb::DefectLocation::ball;
  q8.bearing_b.defect.width_m = 0.5e-3;
  q8.bearing_b.defect.depth_m = 0.0;
  mb::Rotor8DofModel m8, n8;
  ASSERT_TRUE(m8.configure(p8));
  ASSERT_TRUE(n8.configure(q8));
  mb::Rotor8DofState y = mb::Rotor8DofState::Zero(), z = y;
  std::function<double(double)> sp = [](double) { return 30.0; };
  double t = 0;
  for (int i = 0; i < 20000; ++i, t += p8.step_s) {
    m8.step(y, t, sp);
    n8.step(z, t, sp);
  }
  EXPECT_TRUE(y == z) << "a zero-depth ball spot changed the 8-DOF state";
}

// Clean record (constant speed, no noise): the envelope's strongest defect lines are 2 x BSF
// (the spot meets both races once per spin), with sidebands +-FTF and the FTF line itself (the
// spot ball goes round with the cage through the load zone); the healthy model has none of them.
TEST(BallSpot, CleanEnvelopeHasTwiceBsfModulatedAtFtf) {
  const double fs_hz = 20000.0, speed_hz = 30.0, duration_s = 4.0;
  auto speed = [&](double) { return speed_hz; };
  const auto p = ball_spot_6205(1.0e-3, 0.6e-3);
  mb::Hertz4DofParams ph = p;
  ph.defect = {};
  const auto x = mb::simulate_housing_acceleration(p, speed, fs_hz, duration_s, 0.0, 1);
  const auto xh = mb::simulate_housing_acceleration(ph, speed, fs_hz, duration_s, 0.0, 1);
  const DirectEnvelope e(x, fs_hz), eh(xh, fs_hz);
  const auto kin = mb::defect_frequencies(p.bearing, speed_hz);
  const double f2 = 2.0 * kin.bsf_hz, ftf = kin.ftf_hz;
  // 2 x BSF: found within a bin, far above its floor and above the healthy record's level.
  const auto [a2, f2_found] = e.peak(f2);
  std::printf("2 BSF %.2f Hz: found %.2f, / floor %.0f, / healthy %.0f, / BSF line %.1f\n", f2, f2_found,
              a2 / e.floor(f2), a2 / eh.peak(f2).first, a2 / e.peak(kin.bsf_hz).first);
  EXPECT_NEAR(f2_found, f2, e.bin_hz());
  EXPECT_GT(a2, 20.0 * e.floor(f2));
  EXPECT_GT(a2, 10.0 * eh.peak(f2).first);
  // Impacts at 2 x BSF, not 1 x: the BSF line is much weaker.
  EXPECT_GT(a2, 5.0 * e.peak(kin.bsf_hz).first);
  // Load-zone modulation at FTF: the sidebands 2 BSF +- FTF and FTF itself stand out.
  for (double f : {f2 - ftf, f2 + ftf, ftf}) {
    const auto [a, found] = e.peak(f);
    std::printf("%.2f Hz: found %.2f, / floor %.0f, / healthy %.0f\n", f, found, a / e.floor(f), a / eh.peak(f).first);
    EXPECT_NEAR(found, f, e.bin_hz()) << f;
    EXPECT_GT(a, 10.0 * e.floor(f)) << f;
    EXPECT_GT(a, 10.0 * eh.peak(f).first) << f;
  }
  // Not an inner-race signature: the BPFI line is weak beside 2 x BSF.
  std::printf("BPFI line / 2 BSF line %.3f\n", e.peak(kin.bpfi_hz).first / a2);
  EXPECT_LT(e.peak(kin.bpfi_hz).first, 0.1 * a2);
}
