// bearing-check on a measured 10 s, 12 kHz record (CWRU 1797_IR_7_DE12, DE_time, 6205): the whole
// chain (speed refinement, pre-whitening, kurtogram, envelope spectra, family scores, decision).
// Target: <= 1 s. Run: amb-bench --benchmark_filter=BearingCheck
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "model/bearing/catalogue.hpp"
#include "tests/support/test_paths.hpp"

static void BM_BearingCheckCwru10s12k(benchmark::State& state) {
  const std::string path = std::string(amb::test::shared_dir()) + "/data/measured/cwru/1797_IR_7_DE12.mat";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("measured data not found");
    return;
  }
  const auto x = amb::host::read_mat_vector(path, "DE_time");
  const auto g = *amb::model::bearing::find_bearing("6205");
  for (auto _ : state) {
    auto r = amb::host::bearing::check_bearing(x, 12000.0, 1797.0 / 60.0, g);
    benchmark::DoNotOptimize(r.verdict.data());
  }
  state.SetLabel(std::to_string(x.size()) + " samples at 12 kHz");
}
BENCHMARK(BM_BearingCheckCwru10s12k)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
