// Converged wear identification (issue 33): one three-parameter identification of seed 002's
// wear 1 with the film grid refined to 0.2 % estimated K/C error (search on the board's grid,
// then defect-corrected polish on the refined grid), beside the same identification on the
// board's 72 x 12 grid alone (the time before issue 33). The "record" is the forward model's
// spectrum on a 288 x 48 grid (a grid the identification does not search on), noise 0.016 um
// per component (what the SIL's 1 um rms probe noise leaves in a 2 s record's bins).
// Run (median of 3): amb-bench --benchmark_filter=WearIdConverged --benchmark_repetitions=3
//                     --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>

#include "firmware/board/board.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "model/journal/reynolds_fvm.hpp"

namespace {
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;
constexpr double k_deg = M_PI / 180.0;
const mj::WearParams k_wear1{mj::WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg};

// arg 0: grid tolerance 0 (board grid) or 0.002; arg 1: eccentricity x 10 (1 or 7).
void BM_WearIdConverged(benchmark::State& state) {
  const auto b = amb::board::load_board("unicamp-journal-rig");
  auto fine = b;
  fine.journal.grid.cells_theta = 288;
  fine.journal.grid.cells_axial = 48;
  const double eps = 0.1 * static_cast<double>(state.range(1));
  wi::JournalMeasurement m;
  m.speed_hz = 34.0;
  m.journal = {0.0, -eps * b.journal.geometry.clearance_m, 0.0, 0.0};
  m.eccentricity = eps;
  m.spectrum = wi::predict_spectrum(fine, k_wear1, m.journal, m.speed_hz);
  m.noise_m = 1.6e-8;
  wi::WearIdOptions o;
  o.model = mj::WearModel::elliptical;
  o.threads = 2;
  o.grid_tolerance = state.range(0) == 0 ? 0.0 : 2e-3;
  wi::WearIdResult r;
  for (auto _ : state) {
    r = wi::identify_wear(b, m, o);
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["evaluations"] = r.evaluations;
  state.counters["fine_evaluations"] = r.fine_evaluations;
  state.counters["grid_theta"] = r.grid_theta;
  state.counters["grid_axial"] = r.grid_axial;
  state.counters["profile_points"] = r.profile_points;
  state.counters["profile_s"] = r.profile_wall_s;
  state.counters["profile_restarts"] = r.profile_restarts;
  state.counters["identified"] = r.identified ? 1 : 0;
  state.counters["intermediate_evaluations"] = r.intermediate_evaluations;
  state.counters["valleys"] = static_cast<double>(r.valleys.size());
  state.counters["d0_err_pct"] = 100.0 * (r.d0_um / 46.5 - 1.0);
  state.counters["gamma_err_deg"] = r.gamma_deg - 23.0;
  state.counters["beta_err_pct"] = 100.0 * (r.beta_deg / 77.0 - 1.0);
  state.SetLabel(state.range(0) == 0 ? "3p, board grid 72 x 12 only (before issue 33)" : "3p, grid refined to 0.2 % K/C");
}
}  // namespace
BENCHMARK(BM_WearIdConverged)
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 7})
    ->Args({1, 7})
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();
