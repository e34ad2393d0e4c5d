#pragma once
// A drop of the project's penalty plant for the fit tests: friction `mu` on both aux bearings,
// spinning at `spin_hz`, amplifiers cut at the first sample, `seconds` of sensor readings and
// spin speed at 10 kHz (sensor noise as the plant parameters say).
#include <cmath>

#include "host-tools/core/fit/drop_measurement.hpp"
#include "model/plant/rotor_amb_plant.hpp"

namespace amb::test {

inline amb::host::fit::DropMeasurement plant_drop(double mu, double spin_hz, amb::model::PlantParams p, double seconds) {
  for (auto& a : p.aux) a.friction_coefficient = mu;
  amb::model::RotorAmbPlant plant(p);
  plant.reset(true, spin_hz);
  amb::model::PlantInputs in;
  in.amplifiers_enabled = false;
  amb::host::fit::DropMeasurement m;
  m.source = "penalty plant";
  m.rig = "bath-amb-rig";
  m.sample_rate_hz = 1e4;
  m.trigger_index = 0;
  m.speed_at_trigger_hz = spin_hz;
  const int n = static_cast<int>(std::lround(seconds * 1e4));
  for (int i = 0; i < n; ++i) {
    m.sensor_m.push_back(plant.outputs().displacement_m);
    m.speed_rad_s.push_back(2.0 * M_PI * plant.outputs().spin_speed_hz);
    plant.step(1e-4, in);
  }
  return m;
}

}  // namespace amb::test
