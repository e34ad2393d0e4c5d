#pragma once
// One cell of the friction x speed sweep (friction_sweep_test.cpp): a 0.3 s drop of the
// project's penalty plant (sensor noise on, amplifiers cut at the first sample) with friction
// `mu` at `rpm`, read by the contact-force friction estimate.
#include <cmath>

#include "firmware/board/board.hpp"
#include "host-tools/core/fit/friction_estimate.hpp"
#include "model/plant/rotor_amb_plant.hpp"

namespace hf = amb::host::fit;

namespace amb::test {

inline const amb::board::BoardConfig& sweep_board() {
  static const auto b = amb::board::load_board("bath-amb-rig");
  return b;
}

inline hf::DropMeasurement sweep_plant_drop(double mu, double spin_hz) {
  auto p = sweep_board().plant;
  for (auto& a : p.aux) a.friction_coefficient = mu;
  amb::model::RotorAmbPlant plant(p);
  plant.reset(true, spin_hz);
  amb::model::PlantInputs in;
  in.amplifiers_enabled = false;
  hf::DropMeasurement m;
  m.source = "penalty plant";
  m.rig = "bath-amb-rig";
  m.sample_rate_hz = 1e4;
  m.trigger_index = 0;
  m.speed_at_trigger_hz = spin_hz;
  for (int i = 0; i < 3000; ++i) {
    m.sensor_m.push_back(plant.outputs().displacement_m);
    m.speed_rad_s.push_back(2.0 * M_PI * plant.outputs().spin_speed_hz);
    plant.step(1e-4, in);
  }
  return m;
}

struct SweepCell {
  bool valid = false;
  double estimate = 0.0, uncertainty = 0.0, error = 0.0;
  int used = 0;
};

inline SweepCell sweep_cell(double mu, double rpm) {
  const hf::FrictionEstimate e = hf::estimate_friction(sweep_plant_drop(mu, rpm / 60.0), sweep_board().plant);
  SweepCell c;
  c.valid = e.valid;
  c.estimate = e.friction;
  c.uncertainty = e.uncertainty;
  c.error = e.friction / mu - 1.0;
  c.used = e.windows_used;
  return c;
}

}  // namespace amb::test
