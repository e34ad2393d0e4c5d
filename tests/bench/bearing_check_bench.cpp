// bearing-check on a measured 10 s, 12 kHz record (CWRU DE_time, 6205): the whole chain (speed
// refinement, pre-whitening, kurtogram, envelope spectra, family scores, decision).
// arg 0: 1797_IR_7_DE12 (named in the whitened bands), default options; arg 1: 1797_B_7_DE12 with
// the raw cage scan on (--raw-cage-scan; nothing is detected in the whitened bands, so the scan
// with its own surrogate null runs too: the slowest path).
// Target: <= 1 s. Run: amb-bench --benchmark_filter=BearingCheck
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "model/bearing/catalogue.hpp"
#include "tests/support/test_paths.hpp"

static void BM_BearingCheckCwru10s12k(benchmark::State& state) {
  const char* file = state.range(0) == 0 ? "1797_IR_7_DE12" : "1797_B_7_DE12";
  const std::string path = std::string(amb::test::shared_dir()) + "/data/measured/cwru/" + file + ".mat";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("measured data not found");
    return;
  }
  const auto x = amb::host::read_mat_vector(path, "DE_time");
  const auto g = *amb::model::bearing::find_bearing("6205");
  amb::host::bearing::BearingCheckOptions o;
  o.raw_cage_scan = state.range(0) == 1;
  for (auto _ : state) {
    auto r = amb::host::bearing::check_bearing(x, 12000.0, 1797.0 / 60.0, g, o);
    benchmark::DoNotOptimize(r.verdict.data());
  }
  state.SetLabel(std::string(file) + ", " + std::to_string(x.size()) + " samples at 12 kHz" +
                 (o.raw_cage_scan ? ", raw cage scan on" : ""));
}
BENCHMARK(BM_BearingCheckCwru10s12k)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
