// Hybrid model benchmarks (seed 001, issue 34): training on the nine shared CWRU fault records
// (inner race, outer race, ball at 1797 / 1750 / 1730 rpm; 2 threads: nine 4 s simulations,
// the segments' spectra, the maps, the inner cross-validation of the correction and its
// ensemble), and one prediction (the 8-DOF simulation at the point, the transported baselines
// and the corrected ensemble) at 1772 rpm / 1 hp, the point between the training points.
// Targets (issue 34): training <= 5 min on 2 cores, prediction <= 1 s.
// Run: amb-bench --benchmark_filter=Hybrid
#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "host-tools/core/hybrid/hybrid_model.hpp"
#include "tests/hybrid/cwru_nine.hpp"

namespace hy = amb::host::hybrid;

namespace {

std::vector<hy::Record> nine_records() { return amb::test::hybrid::cwru_nine_records(); }

}  // namespace

static void BM_HybridTrainNineRecords(benchmark::State& state) {
  const auto recs = nine_records();
  hy::TrainOptions o;
  o.threads = 2;
  for (auto _ : state) {
    const hy::HybridModel m = hy::train_hybrid(recs, o);
    benchmark::DoNotOptimize(m.psd_correction.trained());
  }
  state.SetLabel("9 CWRU records, 3 operating points, 2 threads");
}
BENCHMARK(BM_HybridTrainNineRecords)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true)->UseRealTime();

static void BM_HybridPredict(benchmark::State& state) {
  hy::TrainOptions o;
  o.threads = 2;
  const hy::HybridModel m = hy::train_hybrid(nine_records(), o);
  for (auto _ : state) {
    const hy::Prediction p = hy::predict_hybrid(m, hy::BearingState::outer_race, {1772.0, 1.0});
    benchmark::DoNotOptimize(p.log_psd_hybrid.data());
  }
  state.SetLabel("outer race at 1772 rpm / 1 hp, model of the 9 records");
}
BENCHMARK(BM_HybridPredict)->Unit(benchmark::kMillisecond)->Iterations(5)->Repetitions(3)->ReportAggregatesOnly(true)->UseRealTime();
