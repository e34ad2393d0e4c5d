// amb-bench: the drop model's speed (simulated seconds per wall second; seed 001's ADAMS
// model needed 36 minutes per simulated second) and the wall time of one full Phase C fit.
#include <chrono>
#include <ctime>
#include <filesystem>

#include <benchmark/benchmark.h>

#include "firmware/board/board.hpp"
#include "model/drop/drop_model.hpp"
#include "model/drop/drop_simulation.hpp"
#if __has_include("host-tools/core/fit/drop_fit.hpp")
#include "host-tools/core/fit/drop_fit.hpp"
#define AMB_DROP_BENCH_FIT 1
#endif

namespace md = amb::model::drop;

namespace {

const amb::board::BoardConfig& bath() {
  static const auto b = amb::board::load_board("bath-amb-rig");
  return b;
}

// Full model (board's 12 modes per plane, h = 20 us): levitated 0.1 s, then a 0.5 s drop.
void BM_DropModelRealTime(benchmark::State& state) {
  md::DropModel m(bath().plant, bath().controller, bath().rate_hz, md::DropOptions{});
  m.set_friction_coefficient(0.15);
  md::DropScenario sc;
  sc.window_s = 0.5;
  double simulated = 0.0, wall = 0.0, cpu = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();  // process CPU time: the machine is shared, wall time depends on its load
    const auto tr = md::simulate_drop(m, sc, false);
    cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    simulated += sc.settle_s + sc.pre_trigger_s + sc.window_s;
    benchmark::DoNotOptimize(tr.samples.back().spin_rad_s);
  }
  state.counters["sim_s_per_wall_s"] = simulated / wall;
  state.counters["sim_s_per_cpu_s"] = simulated / cpu;
}
BENCHMARK(BM_DropModelRealTime)->Unit(benchmark::kMillisecond)->Iterations(5);

#ifdef AMB_DROP_BENCH_FIT
// One full fit (DOE + implicit filtering, both cores) of a generated drop (mu = 0.2).
void BM_DropFit(benchmark::State& state) {
  md::DropOptions o;
  o.noise_seed = 99;
  md::DropModel gen(bath().plant, bath().controller, bath().rate_hz, o);
  gen.set_friction_coefficient(0.2);
  md::DropScenario sc;
  sc.window_s = 0.4;
  sc.pre_trigger_s = 0.02;
  const auto tr = md::simulate_drop(gen, sc, false);
  amb::host::fit::DropMeasurement m;
  m.rig = "bath-amb-rig";
  m.sample_rate_hz = sc.sample_rate_hz;
  m.trigger_index = tr.trigger_index;
  m.speed_at_trigger_hz = sc.speed_hz;
  for (const auto& s : tr.samples) {
    m.sensor_m.push_back(s.sensor_m);
    m.speed_rad_s.push_back(s.spin_rad_s);
  }
  double mu = 0.0, wall = 0.0;
  int evals = 0;
  for (auto _ : state) {
    const auto r = amb::host::fit::fit_drop(m, bath(), amb::host::fit::DropFitOptions{});
    mu = r.friction_coefficient;
    wall = r.wall_s;
    evals = r.evaluations;
  }
  state.counters["fit_wall_s"] = wall;
  state.counters["evaluations"] = evals;
  state.counters["mu_fitted_true_0.2"] = mu;
}
BENCHMARK(BM_DropFit)->Unit(benchmark::kSecond)->Iterations(1);
#endif

}  // namespace
