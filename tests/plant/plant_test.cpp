// The simulated rig: drop onto the touchdown bearings, rest, energy, unbalance orbit,
// faults, determinism and the no-allocation guarantee of step().
#include <gtest/gtest.h>

#include <array>
#include <cmath>
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
