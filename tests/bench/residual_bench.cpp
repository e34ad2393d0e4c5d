// amb-bench: `amb-host residual` on one drop event (issue 31: <= 30 s wall on the 2-core
// machine, median): run_drop_residual on the shared synthetic drops 3 (an aux-bearing offset)
// and 4 (a sensor runout), the whole loop as the command runs it (levitated part, drop fit,
// contact-geometry candidates, refits).
#if __has_include("host-tools/core/residual/drop_residual.hpp")
#include <chrono>
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "tests/support/test_paths.hpp"

namespace {

void BM_ResidualDropEvent(benchmark::State& state) {
  const std::string path = std::string(amb::test::shared_dir()) + "/data/synthetic/bath_drop_example_" +
                           std::to_string(state.range(0)) + ".json";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("no " + path).c_str());
    return;
  }
  const auto rec = amb::host::load_event(path);
  const auto b = amb::board::load_board(rec.board);
  std::string verdict;
  for (auto _ : state) {
    const auto o = amb::host::residual::run_drop_residual(rec, b);
    verdict = o.verdict;
    benchmark::DoNotOptimize(o.after.rms);
  }
  state.SetLabel(verdict);
}
BENCHMARK(BM_ResidualDropEvent)->Arg(3)->Arg(4)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true)->UseRealTime();

}  // namespace
#endif
