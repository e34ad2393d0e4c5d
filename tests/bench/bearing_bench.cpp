// Bearing model benchmarks: 4-DOF simulation cost and eta identification time, AFSA (seed 003
// reference settings; the seed reports 20-30 s per update in MATLAB) vs zoomed grid + Brent.
// Run: amb-bench --benchmark_filter=Bearing
#include <benchmark/benchmark.h>

#include <cmath>

#include "model/bearing/hertz_4dof.hpp"
#include "model/bearing/stiffness_identification.hpp"

namespace mb = amb::model::bearing;

namespace {
mb::Hertz4DofParams rig(double eta) {
  mb::Hertz4DofParams p;
  p.defect.location = mb::DefectLocation::outer_race;
  p.defect.width_m = 0.5e-3;
  p.defect.depth_m = 0.3e-3;
  p.defect.angle_rad = M_PI / 2;
  p.stiffness_scale = eta;
  return p;
}
double speed_hz(double) { return 5000.0 / 60.0; }
}  // namespace

static void BM_BearingSimulate1s(benchmark::State& state) {
  const auto p = rig(1.0);
  for (auto _ : state) {
    auto x = mb::simulate_housing_acceleration(p, speed_hz, 20000.0, 1.0, 0.05, 1);
    benchmark::DoNotOptimize(x.data());
  }
  state.SetLabel("1 s of housing acceleration at 20 kHz, 6206 outer-race groove, 5000 rpm");
}
BENCHMARK(BM_BearingSimulate1s)->Unit(benchmark::kMillisecond);

// One identification on a 0.5 s record (eta_true 1.3, noise 0.05 m/s^2); arg 0: Brent, 1: AFSA.
static void BM_BearingEtaIdentification(benchmark::State& state) {
  const bool afsa = state.range(0) == 1;
  const auto measured = mb::simulate_housing_acceleration(rig(1.3), speed_hz, 20000.0, 0.5, 0.05, 11);
  mb::StiffnessIdOptions o;
  o.fs_hz = 20000.0;
  o.method = afsa ? mb::EtaMethod::afsa : mb::EtaMethod::brent;
  mb::StiffnessIdSummary s;
  for (auto _ : state) s = mb::identify_stiffness_scale(rig(1.0), speed_hz, measured, o);
  state.counters["eta"] = s.eta;
  state.counters["eta_err_pct"] = 100.0 * (s.eta / 1.3 - 1.0);
  state.counters["evaluations"] = s.evaluations;
  state.SetLabel(afsa ? "AFSA (seed 003: swarm 20, 15 iterations)" : "zoomed log grid + Brent");
}
BENCHMARK(BM_BearingEtaIdentification)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1);
