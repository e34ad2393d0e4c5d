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
  std::array<amb::fw::AxisTransform, 2> xf;
  std::array<amb::fw::PidAxis, 4> pid;
  for (size_t b = 0; b < 2; ++b) {
    xf[b].configure({board.plant.sensor[2 * b].angle_deg, board.plant.sensor[2 * b + 1].angle_deg},
                    board.plant.amb[b].actuator_angle_deg);
    for (size_t d = 0; d < 2; ++d) {
      pid[2 * b + d].configure(board.controller, board.rate_hz, board.plant.amb[b].ki_n_per_a);
      pid[2 * b + d].reset();
    }
  }
  for (auto _ : state) {
    const amb::model::PlantOutputs o = plant.outputs();
    for (size_t b = 0; b < 2; ++b) {
      const auto xy = xf[b].sensors_to_xy({o.displacement_m[2 * b], o.displacement_m[2 * b + 1]});
      bool sat = false;
      const auto f = xf[b].xy_to_actuators({pid[2 * b].step(xy[0], 0.0, sat), pid[2 * b + 1].step(xy[1], 0.0, sat)});
      in.current_demand_a[2 * b] = f[0] / board.plant.amb[b].ki_n_per_a;
      in.current_demand_a[2 * b + 1] = f[1] / board.plant.amb[b].ki_n_per_a;
    }
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
