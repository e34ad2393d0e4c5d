// The discrete PID, its notch filters and the +-45 deg axis transformation.
#include <gtest/gtest.h>

#include <cmath>

#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"

using amb::fw::AxisTransform;
using amb::fw::PidAxis;
using amb::model::PidParams;

namespace {
PidParams gains(double kp, double ki, double kd) {
  PidParams p;
  p.kp_n_per_m = kp;
  p.ki_n_per_m_s = ki;
  p.kd_n_s_per_m = kd;
  p.derivative_filter_hz = 1000.0;
  p.integrator_limit_n = 100.0;
  p.current_limit_a = 10.0;
  return p;
}
}  // namespace

TEST(Pid, ProportionalIsRestoring) {
  PidAxis pid;
  pid.configure(gains(1e6, 0, 0), 10000.0, 1000.0);
  bool sat = false;
  EXPECT_NEAR(pid.step(1e-5, 0.0, sat), -10.0, 1e-9);
  EXPECT_FALSE(sat);
  EXPECT_NEAR(pid.step(-2e-5, 0.0, sat), 20.0, 1e-9);
}

TEST(Pid, IntegratorIsClampedForAntiWindup) {
  PidAxis pid;
  pid.configure(gains(0, 1e6, 0), 10000.0, 1000.0);
  bool sat = false;
  for (int i = 0; i < 100000; ++i) pid.step(1e-3, 0.0, sat);
  EXPECT_NEAR(pid.integral_force_n(), 100.0, 1e-9);  // the limit, not 1e6 * 1e-3 * 10 s
}

TEST(Pid, DerivativeOfARampReachesKdTimesSlope) {
  PidAxis pid;
  pid.configure(gains(0, 0, 100.0), 10000.0, 1000.0);
  bool sat = false;
  double u = 0;
  const double v = 1e-3;  // m/s
  for (int i = 0; i < 2000; ++i) u = pid.step(v * i * 1e-4, 0.0, sat);
  EXPECT_NEAR(u, -100.0 * v, 1e-6);
}

TEST(Pid, OutputSaturatesAtCurrentLimitTimesKi) {
  PidAxis pid;
  pid.configure(gains(1e9, 1e6, 0), 10000.0, 1000.0);  // limit 10 A * 1000 N/A
  bool sat = false;
  const double u = pid.step(1.0, 0.0, sat);
  EXPECT_TRUE(sat);
  EXPECT_DOUBLE_EQ(u, -10000.0);
}

TEST(Pid, NoIntegrationFurtherIntoSaturation) {
  PidParams p = gains(1e9, 1e6, 0);
  p.integrator_limit_n = 1e9;
  PidAxis pid;
  pid.configure(p, 10000.0, 1000.0);
  bool sat = false;
  for (int i = 0; i < 1000; ++i) pid.step(1e-3, 0.0, sat);
  EXPECT_TRUE(sat);
  EXPECT_NEAR(pid.integral_force_n(), 0.0, 1e-9);
}

TEST(Pid, NotchRemovesItsCentreAndPassesElsewhere) {
  amb::model::NotchParams n{500.0, 50.0, 0.0};
  const double fs = 10000.0;
  auto amplitude = [&](double f) {
    amb::fw::Biquad q = amb::fw::design_notch(n, fs);
    // RMS over whole settled periods (a sampled peak would miss the crest near Nyquist).
    double sum_sq = 0.0;
    int count = 0;
    for (int i = 0; i < 40000; ++i) {
      const double y = q.step(std::sin(2 * M_PI * f * i / fs));
      if (i >= 20000) {
        sum_sq += y * y;
        ++count;
      }
    }
    return std::sqrt(2.0 * sum_sq / count);
  };
  EXPECT_LT(amplitude(500.0), 0.01);
  EXPECT_NEAR(amplitude(50.0), 1.0, 0.01);
  EXPECT_NEAR(amplitude(3000.0), 1.0, 0.01);
  // -3 dB at centre +- width/2.
  EXPECT_NEAR(amplitude(525.0), std::sqrt(0.5), 0.05);
}

TEST(AxisTransform, SensorsAt45DegreesRecoverXY) {
  AxisTransform t;
  t.configure({45.0, -45.0}, {45.0, -45.0});
  const double x = 3e-5, y = -1e-5;
  const double a = M_PI / 4;
  const auto xy = t.sensors_to_xy({x * std::sin(a) + y * std::cos(a), x * std::sin(-a) + y * std::cos(-a)});
  EXPECT_NEAR(xy[0], x, 1e-15);
  EXPECT_NEAR(xy[1], y, 1e-15);
}

TEST(AxisTransform, ActuatorForcesSumToTheDemand) {
  AxisTransform t;
  t.configure({45.0, -45.0}, {45.0, -45.0});
  const auto f = t.xy_to_actuators({0.0, 100.0});  // pure lift
  EXPECT_NEAR(f[0], f[1], 1e-12);                  // both upper coils share it
  const double a = M_PI / 4;
  EXPECT_NEAR(f[0] * std::sin(a) + f[1] * std::sin(-a), 0.0, 1e-12);
  EXPECT_NEAR(f[0] * std::cos(a) + f[1] * std::cos(-a), 100.0, 1e-12);
}
