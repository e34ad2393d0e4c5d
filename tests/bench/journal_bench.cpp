// Journal-bearing benchmarks (seed 002): one Reynolds solve on the board's grid, one set of
// dynamic coefficients (9 solves), and one full wear identification (DOE + BOBYQA polish, 2
// threads) on the board's forward model, for the 3p and 2p models.
// Run: amb-bench --benchmark_filter=Journal
#include <benchmark/benchmark.h>

#include <cmath>

#include "firmware/board/board.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "model/journal/journal_rig.hpp"
#include "model/journal/reynolds_fvm.hpp"

namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;

namespace {
constexpr double k_deg = M_PI / 180.0;
const mj::WearParams k_wear1{mj::WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg};
}  // namespace

static void BM_JournalReynoldsSolve(benchmark::State& state) {
  const auto b = amb::board::load_board("unicamp-journal-rig");
  mj::ReynoldsSolver s(b.journal.geometry, k_wear1, b.journal.grid);
  const mj::JournalState js{0.0, -0.7 * b.journal.geometry.clearance_m, 0.0, 0.0};
  for (auto _ : state) benchmark::DoNotOptimize(s.solve(js, 2.0 * M_PI * 34.0).fy_n);
  state.SetLabel("72 x 12 cells, Reynolds cavitation, wear 1, e = 0.7");
}
BENCHMARK(BM_JournalReynoldsSolve)->Unit(benchmark::kMillisecond);

static void BM_JournalCoefficients(benchmark::State& state) {
  const auto b = amb::board::load_board("unicamp-journal-rig");
  mj::ReynoldsSolver s(b.journal.geometry, k_wear1, b.journal.grid);
  const mj::JournalState js{0.0, -0.7 * b.journal.geometry.clearance_m, 0.0, 0.0};
  for (auto _ : state) benchmark::DoNotOptimize(mj::perturbation_coefficients(s, js, 2.0 * M_PI * 34.0).fx0_n);
  state.SetLabel("K and C by central differences (9 solves)");
}
BENCHMARK(BM_JournalCoefficients)->Unit(benchmark::kMillisecond);

// One identification; arg 0: 3p, 1: 2p. The "measurement" is the forward model's spectrum
// of wear 1 at e = 0.1 (no SIL in a benchmark).
static void BM_JournalWearIdentification(benchmark::State& state) {
  const auto b = amb::board::load_board("unicamp-journal-rig");
  wi::JournalMeasurement m;
  m.speed_hz = 34.0;
  m.journal = {0.0, -0.1 * b.journal.geometry.clearance_m, 0.0, 0.0};
  m.eccentricity = 0.1;
  m.spectrum = wi::predict_spectrum(b, k_wear1, m.journal, m.speed_hz);
  m.noise_m = 1e-8;
  wi::WearIdOptions o;
  o.model = state.range(0) == 0 ? mj::WearModel::elliptical : mj::WearModel::two_parameter;
  o.threads = 2;
  int evals = 0;
  for (auto _ : state) {
    const wi::WearIdResult r = wi::identify_wear(b, m, o);
    evals = r.evaluations;
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["evaluations"] = evals;
  state.SetLabel(state.range(0) == 0 ? "3p: DOE 9^3 + 8 BOBYQA polishes + grid neighbours, 2 threads" : "2p: DOE 9^2 + 8 BOBYQA polishes + grid neighbours, 2 threads");
}
BENCHMARK(BM_JournalWearIdentification)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();
