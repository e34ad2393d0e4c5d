// Phase C fit on drops the drop model did not generate: the project's penalty plant
// (model/plant RotorAmbPlant: explicit sub-steps, Kelvin-Voigt contact, sqrt-regularised
// friction), levitated centre, amplifiers cut at the first sample, sensor noise on. The fit
// runs the board's law (Hertz for the Bath rig) and is told nothing about the plant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "firmware/board/board.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "tests/drop/plant_drop.hpp"
#include "tests/support/bath_board.hpp"

using amb::test::bath_board;

namespace hf = amb::host::fit;

TEST(PlantDropFit, RecoversFrictionBouncingAndBackwardWhirl) {
  struct Case {
    double mu, spin_hz;
    amb::model::PlantParams p;
  };
  auto whirling = bath_board().plant;  // a heavy ring and unbalance: backward whirl at mu 0.4
  for (auto& a : whirling.aux) a.ring_inertia_kg_m2 = 2e-3;
  for (auto& d : whirling.rotor.disks) d.unbalance_kg_m = 1e-4;
  const Case cases[] = {{0.15, 45.0, bath_board().plant}, {0.4, 45.0, whirling}};
  for (const auto& c : cases) {
    const hf::DropMeasurement m = amb::test::plant_drop(c.mu, c.spin_hz, c.p, 0.4);
    amb::board::BoardConfig b = bath_board();
    b.plant = c.p;
    for (auto& a : b.plant.aux) a.friction_coefficient = 0.15;  // the board's assumption, not the truth
    const hf::DropFitResult r = hf::fit_drop(m, b, hf::DropFitOptions{});
    std::printf("mu %.3f: fitted %.4f +- %.4f (%+.2f %%), whirl A %s %.1f Hz, %d evaluations, %.1f s, %s\n", c.mu,
                r.friction_coefficient, r.friction_uncertainty, 100.0 * (r.friction_coefficient / c.mu - 1.0),
                r.whirl[0].direction.c_str(), r.whirl[0].frequency_hz, r.evaluations, r.wall_s, r.stop_reason.c_str());
    EXPECT_EQ(r.whirl[0].direction, r.fitted_whirl[0].direction);
    if (c.mu > 0.3) {
      // Known limit (docs/drop-model.md): in sustained backward whirl the Hertz model's
      // friction is off (+21 % here); the whirl itself is classified and reproduced.
      EXPECT_EQ(r.whirl[0].direction, "backward");
      EXPECT_NEAR(r.fitted_whirl[0].frequency_hz, r.whirl[0].frequency_hz, 0.15 * r.whirl[0].frequency_hz);
    } else {
      EXPECT_NEAR(r.friction_coefficient, c.mu, 0.03 * c.mu);
      EXPECT_FALSE(r.bound_active);
    }
  }
}

// A drop whose trigger comes late (the board's detection delay after an AMB cut): the rotor
// reaches its aux bearing at the trigger, so there is no free fall after it. The fit takes the
// rigid-body state at the trigger from the samples before it (DropFitOptions::
// state_from_pre_trigger); without that the model falls from the levitated centre, ~9 ms
// behind the record, and its first impacts miss (the main job's Phase C fitted a bouncing
// model to a backward-whirling record that way). One simulation per variant: every unknown off.
TEST(PlantDropFit, LateTriggerTakesTheStateFromBeforeTheTrigger) {
  hf::DropMeasurement m = amb::test::plant_drop(0.15, 45.0, bath_board().plant, 0.3);
  // Trigger on the first sample whose aux-plane orbit radius reaches 0.9 of the clearance.
  const amb::model::drop::SensorOrbit view(bath_board().plant);
  int trig = -1;
  for (size_t i = 0; i < m.sensor_m.size() && trig < 0; ++i)
    for (int k = 0; k < 2; ++k) {
      const auto p = view.at_aux_plane(m.sensor_m[i], k);
      if (std::hypot(p[0], p[1]) >= 0.9 * bath_board().plant.aux[static_cast<size_t>(k)].clearance_m) trig = static_cast<int>(i);
    }
  ASSERT_GT(trig, 20) << "the plant's free fall should take ~9 ms";
  m.trigger_index = trig;
  m.speed_at_trigger_hz = m.speed_rad_s[static_cast<size_t>(trig)] / (2.0 * M_PI);
  hf::DropFitOptions o;
  o.fit_contact_stiffness = o.fit_contact_damping = o.fit_ring_drag = false;
  o.polish = false;
  o.max_window_s = 0.1;
  o.weights.orbit_window_s = 0.003;  // the approach and the first impact, before the contact law matters
  const hf::DropFitResult with = hf::fit_drop(m, bath_board(), o);
  o.state_from_pre_trigger = false;
  const hf::DropFitResult without = hf::fit_drop(m, bath_board(), o);
  std::printf("late trigger at sample %d: orbit term %.4f with the pre-trigger state (%d samples, residual %.2f um), "
              "%.4f without\n",
              trig, with.cost.orbit, with.free_fall_samples, with.free_fall_residual_rms_m * 1e6, without.cost.orbit);
  EXPECT_EQ(with.free_fall_samples, -o.pre_trigger_fit_samples);
  EXPECT_EQ(without.free_fall_samples, 0);
  // The record's first 15 ms (fall, first impacts) followed to within a tenth of the clearance
  // RMS with the state; a whole clearance-scale miss without it.
  EXPECT_LT(with.cost.orbit, 0.1);
  EXPECT_GT(without.cost.orbit, 3.0 * with.cost.orbit);
}
