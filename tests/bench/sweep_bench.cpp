// The host's analysis of one loop-sensitivity sweep record (issue 35): the Bath rig swept on its
// four axes in SIL (tests/sweep_analysis/sweep_sil.hpp: 48 lines 20-1000 Hz, 8 periods of
// 2000 samples per axis), made once; then
//   BM_SweepEstimate: H1/H2, coherence, bands, peaks and zones (sweep_estimate.hpp);
//   BM_SweepAnalysis: the whole analyse_sweep() -- estimate, the board's model at the lines,
//     the residual loop (three candidates fitted with NLopt, the engine's decision).
#include <benchmark/benchmark.h>

#include <string>

#include "host-tools/core/sweep/sweep_analysis.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/sweep_analysis/sweep_sil.hpp"

namespace {

const amb::board::BoardConfig& bath() {
  static const amb::board::BoardConfig b =
      amb::board::load_board(std::string(amb::test::source_dir()) + "/boards/bath-amb-rig.toml");
  return b;
}

const amb::host::sweep::SweepRecord& record() {
  static const amb::host::sweep::SweepRecord r = amb::test::run_sil_sweep(bath(), {});
  return r;
}

void BM_SweepEstimate(benchmark::State& st) {
  const auto& r = record();
  for (auto _ : st) benchmark::DoNotOptimize(amb::host::sweep::estimate_sweep(r));
}
BENCHMARK(BM_SweepEstimate)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);

void BM_SweepAnalysis(benchmark::State& st) {
  const auto& r = record();
  for (auto _ : st) benchmark::DoNotOptimize(amb::host::sweep::analyse_sweep(r, bath()));
}
BENCHMARK(BM_SweepAnalysis)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true)->UseRealTime();

}  // namespace
