// Phase B on synthetic windows (fast, independent of the plant): each Fig. 2 branch is taken
// for its signature and only for it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "firmware/app/supervisor.hpp"
#include "firmware/diagnosis/phase_b.hpp"

namespace {
using namespace amb::fw;
using diag::FaultType;

constexpr double k_fs = 10000.0;
constexpr size_t k_pre = 5000, k_n = 7000;
constexpr double k_speed = 45.0;

struct Shape {
  std::function<double(double t)> radius_m = [](double) { return 20e-6; };           // 1x orbit radius
  std::function<std::array<double, 2>(double t)> centre_m = [](double) { return std::array<double, 2>{0, 0}; };
  std::function<double(double t, size_t k)> current_extra_a = [](double, size_t) { return 0.0; };  ///< asked for by the controller
  std::function<double(double t, size_t k)> amplifier_extra_a = [](double, size_t) { return 0.0; };  ///< added by the amplifier
  std::function<double(double t)> disp_extra_m = [](double) { return 0.0; };
  int dead_channel = -1;
  double dead_from_s = 1e9;
};

std::vector<LoopSample> make(const Shape& sh) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<LoopSample> v(k_n);
  const double a = M_PI / 4;
  for (size_t i = 0; i < k_n; ++i) {
    const double t = static_cast<double>(i) / k_fs;
    LoopSample& s = v[i];
    s.seq = i;
    s.t_ns = static_cast<int64_t>(i) * 100000;
    s.speed_hz = static_cast<float>(k_speed);
    s.state = static_cast<uint8_t>(State::running);
    s.phase = static_cast<uint8_t>(Phase::at_speed);
    s.flags = flag_amplifiers_enabled | flag_levitated;
    const double r = sh.radius_m(t), ph = 2 * M_PI * k_speed * t;
    const auto c = sh.centre_m(t);
    const double extra = sh.disp_extra_m(t);
    for (size_t b = 0; b < 2; ++b) {
      const double x = c[0] + r * std::cos(ph) + extra + 0.5e-6 * noise(rng);
      const double y = c[1] + r * std::sin(ph) + 0.5e-6 * noise(rng);
      s.displacement_m[2 * b] = static_cast<float>(x * std::sin(a) + y * std::cos(a));
      s.displacement_m[2 * b + 1] = static_cast<float>(-x * std::sin(a) + y * std::cos(a));
      for (size_t k = 0; k < 2; ++k) {
        // Controller-like current: proportional to the reading along the axis, plus noise.
        const size_t j = 2 * b + k;
        const double dem = 7000.0 * s.displacement_m[j] + 0.005 * noise(rng) + sh.current_extra_a(t, j);
        s.current_demand_a[j] = static_cast<float>(dem);
        s.coil_current_a[j] = static_cast<int>(j) == sh.dead_channel && t >= sh.dead_from_s
                                  ? 0.0f
                                  : static_cast<float>(dem + sh.amplifier_extra_a(t, j));
      }
    }
  }
  return v;
}

diag::Diagnosis run(const std::vector<LoopSample>& v) {
  diag::DiagnosisInput in;
  in.samples = v;
  in.trigger_index = k_pre;
  in.rate_hz = k_fs;
  return diag::diagnose(in);
}

TEST(PhaseB, Healthy) {
  const auto d = run(make({}));
  EXPECT_EQ(d.type, FaultType::not_modeled) << d.summary;
  EXPECT_GT(d.confidence, 0.6);
}

TEST(PhaseB, Cutoff) {
  Shape sh;
  sh.dead_channel = 2;
  sh.dead_from_s = 0.49;
  sh.current_extra_a = [](double t, size_t k) { return k == 2 && t > 0.49 ? 0.6 : 0.0; };
  const auto d = run(make(sh));
  EXPECT_EQ(d.type, FaultType::channel_cutoff) << d.summary;
  EXPECT_EQ(d.cutoff_channels, 0x4);
  EXPECT_EQ(d.current_factor[2], 0.0);
}

TEST(PhaseB, DisturbanceAheadOfTheDeflection) {
  Shape sh;
  sh.amplifier_extra_a = [](double t, size_t k) { return k == 0 && t > 0.45 ? 0.5 * std::sin(2 * M_PI * 73.0 * (t - 0.45)) : 0.0; };
  sh.disp_extra_m = [](double t) { return t > 0.455 ? 30e-6 * std::sin(2 * M_PI * 73.0 * (t - 0.455)) : 0.0; };
  const auto d = run(make(sh));
  EXPECT_EQ(d.type, FaultType::current_disturbance) << d.summary;
  EXPECT_NEAR(d.disturbance_frequency_hz, 73.0, 0.5);
  EXPECT_NEAR(d.disturbance_amplitude_a, 0.5, 0.1);
  EXPECT_GT(d.current_lead_s, 0.002);
}

TEST(PhaseB, SynchronousChangeIsNotADisturbance) {
  // A 1x change seen first in the currents is still not a disturbance (it is the rotor's own).
  Shape sh;
  sh.current_extra_a = [](double t, size_t k) { return k == 0 && t > 0.45 ? 0.3 * std::sin(2 * M_PI * k_speed * t) : 0.0; };
  const auto d = run(make(sh));
  EXPECT_NE(d.type, FaultType::current_disturbance) << d.summary;
}

TEST(PhaseB, RisingOneTimesRadiusIsChangingUnbalance) {
  Shape sh;
  sh.radius_m = [](double t) { return 20e-6 + 150e-6 * t; };
  const auto d = run(make(sh));
  EXPECT_EQ(d.type, FaultType::changing_unbalance) << d.summary;
  EXPECT_GT(d.radius_1x_end_m[0], 1.5 * d.radius_1x_start_m[0]);
}

TEST(PhaseB, MovingCentreWithSteadyRadiusIsMisalignment) {
  Shape sh;
  const double dir = -120.0 * M_PI / 180.0;
  sh.centre_m = [dir](double t) { return std::array<double, 2>{80e-6 * t * std::sin(dir), 80e-6 * t * std::cos(dir)}; };
  const auto d = run(make(sh));
  EXPECT_EQ(d.type, FaultType::misalignment) << d.summary;
  EXPECT_NEAR(d.misalignment_direction_deg, -120.0, 5.0);
}

TEST(PhaseB, ShortHistoryIsNotEvaluated) {
  auto v = make({});
  diag::DiagnosisInput in;
  in.samples = v;
  in.trigger_index = 50;
  in.rate_hz = k_fs;
  EXPECT_EQ(diag::diagnose(in).type, FaultType::not_evaluated);
}

}  // namespace
