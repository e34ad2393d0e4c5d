// Plant step cost: one 100 us control period of the simulated rig (all sub-steps), levitated
// by a fixed PD current demand (contact-free) and during a drop (contacts active), for both
// boards. Simulated seconds per wall second = 1e-4 s / (time per iteration).
//   amb-bench --benchmark_filter=Plant
#include <benchmark/benchmark.h>

#include <array>
#include <string>

#include "firmware/board/board.hpp"
#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "tests/support/firmware_control_law.hpp"
#include "tests/support/test_paths.hpp"

namespace {

constexpr double k_period_s = 1e-4;

amb::board::BoardConfig board_for(const char* name) {
  return amb::board::load_board(std::string(amb::test::source_dir()) + "/boards/" + name + ".toml");
}

void report(benchmark::State& state, const amb::model::RotorAmbPlant& plant) {
  state.counters["sim_s_per_wall_s"] =
      benchmark::Counter(k_period_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["substeps_per_period"] = k_period_s / plant.integration_step_s();
  state.counters["modes_per_plane"] = plant.reduced_rotor().modes;
}

// Levitated at the centre by the firmware's PID (PidAxis + AxisTransform, ~1 % of the cost),
// spinning at 45 Hz with unbalance: no contact.
void BM_PlantStepLevitated(benchmark::State& state, const char* name) {
  const auto board = board_for(name);
  amb::model::RotorAmbPlant plant(board.plant);
  plant.reset(true, 45.0);
  amb::model::PlantInputs in;
  in.amplifiers_enabled = true;
  in.spin_speed_command_hz = 45.0;
  amb::test::FirmwareControlLaw law(board, board.plant);
  for (auto _ : state) {
    in.current_demand_a = law.demands_a(plant.outputs().displacement_m);
    plant.step(k_period_s, in);
    benchmark::DoNotOptimize(plant.outputs());
  }
  report(state, plant);
  state.counters["contact_substeps"] = static_cast<double>(plant.counters().contact_substeps);
}

// Drop: amplifiers off from 45 Hz, contacts and friction active most of the time.
void BM_PlantStepDrop(benchmark::State& state, const char* name) {
  const auto board = board_for(name);
  amb::model::RotorAmbPlant plant(board.plant);
  plant.reset(false, 45.0);
  amb::model::PlantInputs in;
  long k = 0;
  for (auto _ : state) {
    if (++k % 20000 == 0) plant.reset(false, 45.0);  // keep it rubbing
    plant.step(k_period_s, in);
    benchmark::DoNotOptimize(plant.outputs());
  }
  report(state, plant);
}

BENCHMARK_CAPTURE(BM_PlantStepLevitated, bath, "bath-amb-rig");
BENCHMARK_CAPTURE(BM_PlantStepLevitated, unicamp, "unicamp-amb-rig");
BENCHMARK_CAPTURE(BM_PlantStepDrop, bath, "bath-amb-rig");
BENCHMARK_CAPTURE(BM_PlantStepDrop, unicamp, "unicamp-amb-rig");

}  // namespace
