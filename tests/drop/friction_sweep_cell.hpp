#pragma once
// One cell of the friction x speed sweep (friction_sweep_test.cpp): a 0.3 s drop of the
// project's penalty plant (sensor noise on, amplifiers cut at the first sample) with friction
// `mu` at `rpm`, read by the contact-force friction estimate.
#include <cmath>

#include "firmware/board/board.hpp"
#include "host-tools/core/fit/friction_estimate.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "tests/drop/plant_drop.hpp"
#include "tests/support/bath_board.hpp"

namespace hf = amb::host::fit;

namespace amb::test {

struct SweepCell {
  bool valid = false;
  double estimate = 0.0, uncertainty = 0.0, error = 0.0;
  int used = 0;
};

inline SweepCell sweep_cell(double mu, double rpm) {
  const hf::FrictionEstimate e = hf::estimate_friction(plant_drop(mu, rpm / 60.0, bath_board().plant, 0.3), bath_board().plant);
  SweepCell c;
  c.valid = e.valid;
  c.estimate = e.friction;
  c.uncertainty = e.uncertainty;
  c.error = e.friction / mu - 1.0;
  c.used = e.windows_used;
  return c;
}

}  // namespace amb::test
