// The simulated rig: drop onto the touchdown bearings, rest, energy, unbalance orbit,
// faults, determinism and the no-allocation guarantee of step().
#define AMB_DEFINE_ALLOC_COUNTER
#include "tests/firmware/alloc_counter.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>

#include "model/plant/rotor_amb_plant.hpp"
#include "tests/plant/rig_fixture.hpp"

namespace amb::model {
namespace {

constexpr double k_loop_s = 1e-4;

class PlantRigs : public ::testing::TestWithParam<const char*> {};

struct DropRecord {
  double e0 = 0.0, e_end = 0.0, worst_rise = 0.0, mean_force_n = 0.0;
  std::array<double, 2> mean_y_m{};
  PlantTruth end{};
  double spin_end_hz = 0.0;
};

// Amplifiers off (so the drive is off too) from the centre for `seconds`; averages over the
// last 0.5 s. Energy is checked after every 100 us step.
DropRecord drop(RotorAmbPlant& plant, double spin_hz, double seconds) {
  plant.reset(true, spin_hz);
  PlantInputs in;
  DropRecord r;
  const PlantTruth t0 = plant.truth();
  r.e0 = t0.kinetic_energy_j + t0.potential_energy_j;
  double e_prev = r.e0;
  int n_avg = 0;
  const int n_steps = static_cast<int>(seconds / k_loop_s);
  for (int k = 0; k < n_steps; ++k) {
    plant.step(k_loop_s, in);
    const PlantTruth t = plant.truth();
    const double e = t.kinetic_energy_j + t.potential_energy_j;
    r.worst_rise = std::max(r.worst_rise, e - e_prev);
    e_prev = e;
    if (k >= n_steps - 5000) {
      r.mean_force_n += t.contact_force_n[0] + t.contact_force_n[1];
      r.mean_y_m[0] += t.aux_y_m[0];
      r.mean_y_m[1] += t.aux_y_m[1];
      ++n_avg;
    }
  }
  r.mean_force_n /= n_avg;
  r.mean_y_m[0] /= n_avg;
  r.mean_y_m[1] /= n_avg;
  r.e_end = e_prev;
  r.end = plant.truth();
  r.spin_end_hz = plant.outputs().spin_speed_hz;
  return r;
}

// Amplifiers off at standstill: the rotor falls, bounces and settles at the bottom of both
// rings; on average the contacts carry the weight (flexible modes ring on lightly, Rayleigh
// damping only, hence the average over the last 0.5 s); energy never rises.
TEST_P(PlantRigs, DropComesToRestOnTouchdownBearings) {
  const auto board = test::board_from_repo(GetParam());
  RotorAmbPlant plant(board.plant);
  const DropRecord r = drop(plant, 0.0, 3.0);
  const double weight = plant.rotor_mass_kg() * board.plant.gravity_m_s2;
  std::printf("[ RESULT ] %s drop at standstill: mean aux y = %.4f / %.4f mm (clearance %.3g / %.3g mm), "
              "mean contact %.2f N vs weight %.2f N, E %.4g -> %.4g J, max rise per step %.2g J\n",
              GetParam(), r.mean_y_m[0] * 1e3, r.mean_y_m[1] * 1e3, board.plant.aux[0].clearance_m * 1e3,
              board.plant.aux[1].clearance_m * 1e3, r.mean_force_n, weight, r.e0, r.e_end, r.worst_rise);
  for (size_t b = 0; b < 2; ++b)
    EXPECT_NEAR(r.mean_y_m[b], -board.plant.aux[b].clearance_m, 0.02 * board.plant.aux[b].clearance_m) << b;
  EXPECT_NEAR(r.mean_force_n, weight, 0.02 * weight);
  EXPECT_LE(r.worst_rise, 1e-12 + 1e-9 * std::abs(r.e_end));
  EXPECT_LT(r.e_end, r.e0);
}

// Spinning drop (2700 rpm, seed 000) without unbalance (an unbalance is a prescribed force:
// it feeds energy in): the rings are spun up by friction, the rotor slows, total energy
// (lateral + spin + rings + elastic + contact + gravity) never rises and the friction work
// is part of what was lost.
TEST_P(PlantRigs, SpinningDropDissipatesEnergyByFriction) {
  auto board = test::board_from_repo(GetParam());
  for (auto& d : board.plant.rotor.disks) d.unbalance_kg_m = 0.0;
  RotorAmbPlant plant(board.plant);
  const double spin0_hz = 45.0;
  const DropRecord r = drop(plant, spin0_hz, 1.0);
  std::printf("[ RESULT ] %s drop at %.0f Hz: spin %.2f Hz after 1 s, rings %.1f / %.1f rad/s, friction work %.4g J, "
              "E %.5g -> %.5g J, max rise per step %.2g J\n",
              GetParam(), spin0_hz, r.spin_end_hz, r.end.ring_speed_rad_s[0], r.end.ring_speed_rad_s[1],
              r.end.friction_dissipated_j, r.e0, r.e_end, r.worst_rise);
  EXPECT_LE(r.worst_rise, 1e-9 * std::abs(r.e0));
  EXPECT_GT(r.end.friction_dissipated_j, 0.0);
  EXPECT_LT(r.spin_end_hz, spin0_hz);
  EXPECT_GT(r.end.ring_speed_rad_s[0], 0.0);
  EXPECT_LE(r.e_end + r.end.friction_dissipated_j, r.e0 * (1.0 + 1e-9));
}

// reset(false) puts the rotor at static rest on the rings: it stays there, the contact
// forces equal the weight share of a statically determinate two-support beam.
TEST_P(PlantRigs, RestOnTouchdownBearingsIsStatic) {
  const auto board = test::board_from_repo(GetParam());
  RotorAmbPlant plant(board.plant);
  plant.reset(false, 0.0);
  PlantInputs in;
  for (int k = 0; k < 2000; ++k) plant.step(k_loop_s, in);
  const PlantTruth t = plant.truth();
  const auto& fe = plant.rotor_model();
  const double weight = plant.rotor_mass_kg() * board.plant.gravity_m_s2;
  const double za = board.plant.aux[0].axial_m, zb = board.plant.aux[1].axial_m;
  // Moment balance about each bearing (rigid statics; the shaft's sag does not change it).
  const double fb = weight * (fe.centre_of_mass_m - za) / (zb - za), fa = weight - fb;
  std::printf("[ RESULT ] %s at rest: contact %.2f / %.2f N, statics %.2f / %.2f N, y %.4f / %.4f mm\n", GetParam(),
              t.contact_force_n[0], t.contact_force_n[1], fa, fb, t.aux_y_m[0] * 1e3, t.aux_y_m[1] * 1e3);
  EXPECT_NEAR(t.contact_force_n[0], fa, 0.005 * weight);
  EXPECT_NEAR(t.contact_force_n[1], fb, 0.005 * weight);
  for (size_t b = 0; b < 2; ++b) {
    EXPECT_NEAR(t.aux_y_m[b], -board.plant.aux[b].clearance_m, 0.01 * board.plant.aux[b].clearance_m);
    EXPECT_NEAR(t.aux_x_m[b], 0.0, 1e-7);
  }
}

INSTANTIATE_TEST_SUITE_P(Boards, PlantRigs, ::testing::Values("bath-amb-rig", "unicamp-amb-rig"));

}  // namespace
}  // namespace amb::model

namespace amb::model {
namespace {

// A nearly rigid symmetric rotor (E x 100) with one unbalanced disk at mid-span, held by a
// discrete PD on the true AMB-plane positions (spring k_net = k_c - ks and damper c per
// bearing): at a constant speed below the bounce mode the orbit is a forward 1x circle of
// radius u W^2 / |2 k_net - m W^2 + j W 2 c| (rigid body, unbalance at the centre of mass).
TEST(Plant, UnbalanceGivesForwardSynchronousOrbitOfRightSize) {
  PlantParams p;
  p.rig_name = "unbalance-check";
  p.rotor = test::uniform_beam(0.6, 0.05, 12, 2.1e13);
  p.rotor.modes_kept = 6;
  p.rotor.rayleigh_beta_s = 1e-6;
  const double u = 1e-4, phase_deg = 30.0;
  p.rotor.disks.push_back({0.3, 1.0, 2e-3, 1e-3, u, phase_deg});
  for (size_t b = 0; b < 2; ++b) {
    AmbParams& a = p.amb[b];
    a.axial_m = b == 0 ? 0.1 : 0.5;
    a.gap_m = 1e-3;
    a.ks_n_per_m = 1e5;
    a.ki_n_per_a = 100.0;
    a.bias_current_a = 1.0;
    a.max_force_n = 1e4;
    a.coil_current_limit_a = 1.0;
    a.amplifier_bandwidth_hz = 1e4;
    a.actuator_angle_deg = {45.0, -45.0};
    p.aux[b] = AuxBearingParams{b == 0 ? 0.02 : 0.58, 5e-3, 1e8, 100.0, 0.1, 0.02, 1e-5, 0.0, 0.0, 0.0};
  }
  for (size_t k = 0; k < 4; ++k) p.sensor[k] = {p.amb[k / 2].axial_m, k % 2 == 0 ? 45.0 : -45.0, 0.0, 0.0};
  p.drive_torque_limit_n_m = 50.0;
  p.drive_speed_gain_n_m_s = 1.0;
  p.integration_step_s = 1e-5;
  p.gravity_m_s2 = 0.0;  // keeps the AMBs at their linearisation point (no static bias current)
  RotorAmbPlant plant(p);
  const double mass = plant.rotor_mass_kg();
  const double wb = 2.0 * M_PI * 80.0, k_net = 0.5 * mass * wb * wb, c = 0.1 * mass * wb;
  const double kc = k_net + p.amb[0].ks_n_per_m;
  const double spin_hz = 40.0, w = 2.0 * M_PI * spin_hz;

  plant.reset(true, spin_hz);
  PlantInputs in;
  in.amplifiers_enabled = true;
  in.spin_speed_command_hz = spin_hz;
  std::array<double, 4> z_prev{};
  auto axis_positions = [&](const PlantTruth& t) {
    std::array<double, 4> z{};
    for (size_t j = 0; j < 4; ++j) {
      const double a = (j % 2 == 0 ? 45.0 : -45.0) * M_PI / 180.0;
      z[j] = std::sin(a) * t.amb_x_m[j / 2] + std::cos(a) * t.amb_y_m[j / 2];
    }
    return z;
  };
  z_prev = axis_positions(plant.truth());
  const int per_rev = 250;  // 40 Hz at 10 kHz
  const int settle = 2 * 10000, record = 20 * per_rev;
  std::vector<double> xs, ys, th;
  for (int k = 0; k < settle + record; ++k) {
    const auto z = axis_positions(plant.truth());
    for (size_t j = 0; j < 4; ++j)
      in.current_demand_a[j] = -(kc * z[j] + c * (z[j] - z_prev[j]) / k_loop_s) / p.amb[0].ki_n_per_a;
    z_prev = z;
    plant.step(k_loop_s, in);
    if (k >= settle) {
      const PlantTruth t = plant.truth();
      xs.push_back(0.5 * (t.amb_x_m[0] + t.amb_x_m[1]));
      ys.push_back(0.5 * (t.amb_y_m[0] + t.amb_y_m[1]));
      th.push_back(plant.outputs().spin_angle_rad);
    }
  }
  // 1x components by correlation with the spin angle over whole revolutions.
  std::complex<double> cx = 0.0, cy = 0.0;
  double mx = 0.0, my = 0.0;
  for (size_t i = 0; i < xs.size(); ++i) {
    mx += xs[i] / xs.size();
    my += ys[i] / ys.size();
  }
  double rmin = 1e9, rmax = 0.0, turn = 0.0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const double dx = xs[i] - mx, dy = ys[i] - my;
    rmin = std::min(rmin, std::hypot(dx, dy));
    rmax = std::max(rmax, std::hypot(dx, dy));
    if (i > 0) turn += (xs[i - 1] - mx) * dy - (ys[i - 1] - my) * dx;  // z-component of r x dr
    cx += dx * std::exp(std::complex<double>(0.0, -th[i]));
    cy += dy * std::exp(std::complex<double>(0.0, -th[i]));
  }
  const double r_model = 0.5 * (rmin + rmax);
  const double r_theory = u * w * w / std::abs(std::complex<double>(2.0 * k_net - mass * w * w, 2.0 * c * w));
  // Where the orbit points when the unbalance points at phase_deg - theta (vertical angle):
  const double lag = std::arg(std::complex<double>(2.0 * k_net - mass * w * w, 2.0 * c * w));
  std::printf("[ RESULT ] unbalance 1x orbit at %.0f Hz: radius %.4f um (min %.4f, max %.4f), theory %.4f um, err %.2f %%, "
              "forward %s, |1x x| %.4f um, |1x y| %.4f um, phase lag theory %.1f deg\n",
              spin_hz, r_model * 1e6, rmin * 1e6, rmax * 1e6, r_theory * 1e6, 100.0 * (r_model / r_theory - 1.0),
              turn > 0.0 ? "yes" : "no", 2.0 * std::abs(cx) / xs.size() * 1e6, 2.0 * std::abs(cy) / ys.size() * 1e6,
              lag * 180.0 / M_PI);
  EXPECT_NEAR(r_model, r_theory, 0.03 * r_theory);
  EXPECT_LT(rmax - rmin, 0.05 * r_theory);  // circular
  EXPECT_GT(turn, 0.0);                     // forward (same sense as the spin, +z)
  // Direction: at spin angle theta the unbalance points at vertical angle (phase - theta);
  // the response lags in time by lag / W, so it points at (phase - theta + lag).
  const double ph = phase_deg * M_PI / 180.0;
  double err = 0.0;
  for (size_t i = 0; i < xs.size(); i += 7) {
    const double ex = r_theory * std::sin(ph - th[i] + lag), ey = r_theory * std::cos(ph - th[i] + lag);
    err = std::max(err, std::hypot(xs[i] - mx - ex, ys[i] - my - ey));
  }
  // Measured lag of the orbit behind the unbalance direction, for the report.
  double lag_meas = 0.0;
  {
    // x = r sin(ph - th - lag) -> 1x coefficient of exp(-i th): (r / 2i) exp(i (ph - lag)) ... use atan2 on samples
    double s1 = 0.0, c1 = 0.0;
    for (size_t i = 0; i < xs.size(); ++i) {
      const double a = std::atan2(xs[i] - mx, ys[i] - my);  // vertical angle of the orbit point
      const double d = std::remainder(ph - th[i] - a, 2.0 * M_PI);
      s1 += std::sin(d);
      c1 += std::cos(d);
    }
    lag_meas = -std::atan2(s1, c1);
  }
  std::printf("[ RESULT ] unbalance orbit lag behind the unbalance: %.1f deg measured, %.1f deg theory\n",
              lag_meas * 180.0 / M_PI, lag * 180.0 / M_PI);
  // The sampled PD's half-sample delay takes a little damping away (lag 6-7 deg instead of 7.6).
  EXPECT_NEAR(lag_meas, lag, 2.0 * M_PI / 180.0);
  EXPECT_LT(err, 0.05 * r_theory);
  EXPECT_LT(err, 0.1 * r_theory);
}

// Determinism and noise: the same seed gives bit-identical outputs, another seed does not;
// the noise has the board's rms.
TEST(Plant, SensorNoiseIsDeterministicAndHasTheBoardRms) {
  const auto board = test::board_from_repo("bath-amb-rig");
  RotorAmbPlant::Options o1, o2;
  o1.noise_seed = 7;
  o2.noise_seed = 8;
  RotorAmbPlant a(board.plant, o1), b(board.plant, o1), c(board.plant, o2);
  for (auto* p : {&a, &b, &c}) p->reset(false, 0.0);
  PlantInputs in;
  double sum2 = 0.0;
  bool differs = false;
  const int n = 4000;
  const double rest = a.outputs().displacement_m[0];
  for (int k = 0; k < n; ++k) {
    a.step(k_loop_s, in);
    b.step(k_loop_s, in);
    c.step(k_loop_s, in);
    for (size_t s = 0; s < 4; ++s) {
      ASSERT_EQ(a.outputs().displacement_m[s], b.outputs().displacement_m[s]);
      differs = differs || a.outputs().displacement_m[s] != c.outputs().displacement_m[s];
    }
    const double e = a.outputs().displacement_m[0] - rest;
    sum2 += e * e;
  }
  EXPECT_TRUE(differs);
  const double rms = std::sqrt(sum2 / n);
  EXPECT_NEAR(rms, board.plant.sensor[0].noise_rms_m, 0.1 * board.plant.sensor[0].noise_rms_m);
}

// Faults: a 0 current factor cuts an axis' control current (bias stays, so the negative
// stiffness and gravity pull the rotor onto the rings); a disturbance appears in the coil
// current at its frequency; disabling the amplifiers removes all current.
TEST(Plant, FaultsActOnTheAmplifierCurrents) {
  const auto board = test::board_from_repo("bath-amb-rig");
  RotorAmbPlant plant(board.plant);
  plant.reset(true, 0.0);
  PlantFaults f;
  f.current_factor = {0.0, 0.0, 0.0, 0.0};
  plant.set_faults(f);
  PlantInputs in;
  in.amplifiers_enabled = true;
  in.current_demand_a = {0.5, 0.5, 0.5, 0.5};
  for (int k = 0; k < 3000; ++k) plant.step(k_loop_s, in);
  for (double i : plant.outputs().coil_current_a) EXPECT_EQ(i, 0.0);
  const PlantTruth t = plant.truth();
  for (size_t b = 0; b < 2; ++b)
    EXPECT_GT(std::hypot(t.aux_x_m[b], t.aux_y_m[b]), 0.95 * board.plant.aux[b].clearance_m) << b;

  PlantFaults d;
  d.disturbance_amplitude_a = {0.2, 0.0, 0.0, 0.0};
  d.disturbance_frequency_hz = 50.0;
  d.disturbance_start_s = 0.0;
  plant.reset(false, 0.0);
  plant.set_faults(d);
  in.current_demand_a = {0.0, 0.0, 0.0, 0.0};
  double peak = 0.0;
  for (int k = 0; k < 400; ++k) {
    plant.step(k_loop_s, in);
    peak = std::max(peak, std::abs(plant.outputs().coil_current_a[0]));
    EXPECT_EQ(plant.outputs().coil_current_a[1], 0.0);
  }
  const double bw = board.plant.amb[0].amplifier_bandwidth_hz;
  EXPECT_NEAR(peak, 0.2 / std::sqrt(1.0 + std::pow(50.0 / bw, 2)), 0.02);
  in.amplifiers_enabled = false;
  plant.step(k_loop_s, in);
  for (double i : plant.outputs().coil_current_a) EXPECT_EQ(i, 0.0);
}

// step() allocates nothing (global operator new counted; Eigen's guard armed as well).
TEST(Plant, StepDoesNotAllocate) {
  const auto board = test::board_from_repo("bath-amb-rig");
  RotorAmbPlant plant(board.plant);
  plant.reset(true, 45.0);
  PlantInputs in;
  in.amplifiers_enabled = true;  // bias on, no control: the negative stiffness pulls it onto the rings
  in.spin_speed_command_hz = 45.0;
  PlantFaults f;
  f.disturbance_amplitude_a = {0.1, 0.1, 0.1, 0.1};
  f.disturbance_frequency_hz = 30.0;
  f.disturbance_start_s = 0.0;
  f.unbalance_growth_start_s = 0.0;
  f.unbalance_growth_kg_m_per_s = 1e-5;
  f.misalignment_start_s = 0.0;
  f.misalignment_rate_m_per_s = 1e-4;
  f.misalignment_stiffness_n_per_m = 1e5;
  plant.set_faults(f);
  const long before = test::allocations();
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < 2000; ++k) plant.step(k_loop_s, in);  // includes the drop and contacts
  (void)plant.outputs();
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(test::allocations() - before, 0);
  EXPECT_GT(plant.counters().contact_substeps, 0u);
}

}  // namespace
}  // namespace amb::model
