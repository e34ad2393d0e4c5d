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

namespace hf = amb::host::fit;

namespace {

const amb::board::BoardConfig& board() {
  static const auto b = amb::board::load_board("bath-amb-rig");
  return b;
}

}  // namespace

TEST(PlantDropFit, RecoversFrictionBouncingAndBackwardWhirl) {
  struct Case {
    double mu, spin_hz;
    amb::model::PlantParams p;
  };
  auto whirling = board().plant;  // a heavy ring and unbalance: backward whirl at mu 0.4
  for (auto& a : whirling.aux) a.ring_inertia_kg_m2 = 2e-3;
  for (auto& d : whirling.rotor.disks) d.unbalance_kg_m = 1e-4;
  const Case cases[] = {{0.15, 45.0, board().plant}, {0.4, 45.0, whirling}};
  for (const auto& c : cases) {
    const hf::DropMeasurement m = amb::test::plant_drop(c.mu, c.spin_hz, c.p, 0.4);
    amb::board::BoardConfig b = board();
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
