// Issue 33: seed 002's Table 2 wears identified from SIL records whose film was computed by
// the independent finite-difference solver (fd_film.hpp, 288 x 48 nodes, K/C within ~0.1 %
// of converged), not by the production film the identification uses (inverse crime avoided).
// The identification runs as `amb-host wear-id` does by default: search on the board's
// grid, then the grid refined to 0.2 % estimated K/C error. One case per wear: e = 0.1 alone and
// the joint fit within targets; e = 0.7 alone within targets when reported identified, else the
// truth inside the reported intervals and inside one acceptable valley's own profile region
// (valleys + profile likelihood, wear_identification.hpp).
// Label long (minutes).
// Run: build/tests/journal/journal_wear_id_independent_tests
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "fd_film.hpp"
#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/wearid/journal_sil_record.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "tests/journal/table2_wears.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;

namespace {
constexpr double k_deg = M_PI / 180.0;
using Wear = amb::test::journal::Table2Wear;
constexpr auto& k_wears = amb::test::journal::k_table2_wears;  // seed 002 Table 2

std::string fd_record(const Wear& w, double ecc, int seed, const char* tag) {
  const std::string dir = std::string(test::artefact_dir()) + "/journal_wear_fd";
  std::filesystem::create_directories(dir);
  const std::string stem =
      dir + "/" + w.tag + "_e" + std::to_string(static_cast<int>(std::lround(ecc * 10))) + "_" + tag;
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const mj::WearParams wear{mj::WearModel::elliptical, w.d0_um * 1e-6, w.gamma_deg * k_deg, w.beta_deg * k_deg};
  wi::JournalSilOptions o;
  o.eccentricity = ecc;
  o.wear = wear;
  o.noise_seed = static_cast<std::uint64_t>(seed);
  o.film = [g = b.journal.geometry, wear](const mj::JournalState& s, double spin) {
    amb::test::journal::FdFilm f(g, wear, 288, 48);
    return f.coefficients(s, spin);
  };
  const wi::JournalSilSummary s = wi::record_journal_sil(o, stem);
  EXPECT_TRUE(s.ok) << s.message;
  EXPECT_NEAR(s.static_eccentricity, ecc, 0.02);
  return stem + ".json";
}

wi::WearIdOptions options() {
  wi::WearIdOptions o;
  o.model = mj::WearModel::elliptical;
  o.grid_tolerance = 2e-3;
  return o;
}

void print(const char* what, const Wear& w, const wi::WearIdResult& r) {
  std::printf("%s %s: d0 %.2f +- %.2f um (%+.1f %%), gamma %.2f +- %.2f deg (%+.2f), beta %.2f +- %.2f deg (%+.1f %%), "
              "cost %.2e, grid %d x %d (est. %.3f %%), %.0f s\n",
              what, w.tag, r.d0_um, r.d0_uncertainty_um, 100 * (r.d0_um / w.d0_um - 1), r.gamma_deg,
              r.gamma_uncertainty_deg, r.gamma_deg - w.gamma_deg, r.beta_deg, r.beta_uncertainty_deg,
              100 * (r.beta_deg / w.beta_deg - 1), r.cost, r.grid_theta, r.grid_axial, 100 * r.grid_error_estimate,
              r.wall_s);
}

bool within(const Wear& w, const wi::WearIdResult& r) {
  return std::abs(r.d0_um / w.d0_um - 1) < 0.05 && std::abs(r.gamma_deg - w.gamma_deg) < 3.0 &&
         std::abs(r.beta_deg / w.beta_deg - 1) < 0.05;
}

bool inside(const std::array<double, 2>& iv, double v) { return iv[0] <= v && v <= iv[1]; }

// The truth lies in the reported intervals (each parameter's).
bool truth_in_reported_intervals(const Wear& w, const wi::WearIdResult& r) {
  return inside(r.d0_interval_um, w.d0_um) && inside(r.gamma_interval_deg, w.gamma_deg) && inside(r.beta_interval_deg, w.beta_deg);
}

// The truth lies in one acceptable valley's intervals (all three parameters in the same valley).
bool truth_in_an_acceptable_valley(const Wear& w, const wi::WearIdResult& r) {
  for (const wi::WearValley& v : r.valleys)
    if (v.acceptable && inside(v.d0_interval_um, w.d0_um) && inside(v.gamma_interval_deg, w.gamma_deg) &&
        inside(v.beta_interval_deg, w.beta_deg))
      return true;
  return false;
}

// For the record only (the identification is never told): the chi2 the truth has on the
// result's refined grid, with the result's sigma (noise and the film's K/C error at the best,
// as identify_wear computes it; one record). Printed beside the level. Returns the truth's
// cost on that grid.
double print_truth_chi2(const board::BoardConfig& b, const std::vector<wi::JournalMeasurement>& ms, const Wear& w,
                      const wi::WearIdResult& r) {
  board::BoardConfig fine = b;
  fine.journal.grid.cells_theta = r.grid_theta;
  fine.journal.grid.cells_axial = r.grid_axial;
  wi::WearIdOptions o = options();
  o.grid_tolerance = 0.0;
  const mj::WearParams truth{mj::WearModel::elliptical, w.d0_um * 1e-6, w.gamma_deg * k_deg, w.beta_deg * k_deg};
  const mj::WearParams best{mj::WearModel::elliptical, r.d0_um * 1e-6, r.gamma_deg * k_deg, r.beta_deg * k_deg};
  const double ct = wi::wear_cost(fine, ms, o, truth), cb = wi::wear_cost(fine, ms, o, best);
  const wi::JournalMeasurement& m = ms.front();
  const std::vector<double> film = wi::film_error_sigma(fine, ms, o, best, r.chi2_film_error);
  const double scale = std::sqrt(std::norm(m.spectrum.forward_m) + std::norm(m.spectrum.backward_m));
  const wi::FullSpectrum z = wi::predict_spectrum(fine, truth, m.journal, m.speed_hz);
  const std::complex<double> f = (z.forward_m - m.spectrum.forward_m) / scale, g = (z.backward_m - m.spectrum.backward_m) / scale;
  const double res[4] = {f.real(), f.imag(), g.real(), g.imag()};
  const double sn = m.noise_m / std::sqrt(2.0) / scale;
  double chi2 = 0.0;
  for (int k = 0; k < 4; ++k) chi2 += res[k] * res[k] / (sn * sn + film[static_cast<size_t>(k)] * film[static_cast<size_t>(k)]);
  std::printf("  truth on the %d x %d grid: cost %.3g (best %.3g): chi2 %.3g against the level %.3g\n", r.grid_theta,
              r.grid_axial, ct, cb, chi2, r.chi2_min + r.chi2_scale * r.chi2_level);
  return ct;
}

// Issue 33, fifth round: the valleys are ranked by chi2 (the statistic the verdict uses), best
// first, and the result is the first.
void expect_ranked_by_chi2(const wi::WearIdResult& r) {
  ASSERT_FALSE(r.valleys.empty());
  EXPECT_EQ(r.valleys.front().chi2, r.chi2_min);
  EXPECT_EQ(r.valleys.front().d0_um, r.d0_um);
  EXPECT_EQ(r.valleys.front().gamma_deg, r.gamma_deg);
  for (size_t k = 1; k < r.valleys.size(); ++k)
    if (std::isfinite(r.valleys[k].chi2)) {
      EXPECT_LE(r.valleys[k - 1].chi2, r.valleys[k].chi2) << "valley " << k;
    }
}

void print_valleys(const wi::WearIdResult& r) {
  std::printf("  identified %d, %d of %zu valleys acceptable (chi2 min %.3g, dof %d, level %.2f x scale %.2f), ambiguous:",
              r.identified, r.acceptable_valleys, r.valleys.size(), r.chi2_min, r.chi2_dof, r.chi2_level, r.chi2_scale);
  for (const std::string& a : r.ambiguous) std::printf(" %s", a.c_str());
  std::printf("\n  intervals d0 %.2f..%.2f um, gamma %.2f..%.2f deg, beta %.2f..%.2f deg; measurable %d (dBIC %.1f)\n",
              r.d0_interval_um[0], r.d0_interval_um[1], r.gamma_interval_deg[0], r.gamma_interval_deg[1],
              r.beta_interval_deg[0], r.beta_interval_deg[1], r.wear_measurable, r.delta_bic);
  for (const wi::WearValley& v : r.valleys)
    std::printf("    valley %.2f um / %.2f deg / %.2f deg: cost %.3g chi2 %.3g %s; d0 %.2f..%.2f, gamma %.2f..%.2f, beta "
                "%.2f..%.2f\n",
                v.d0_um, v.gamma_deg, v.beta_deg, v.cost, v.chi2, v.acceptable ? "acceptable" : "rejected",
                v.d0_interval_um[0], v.d0_interval_um[1], v.gamma_interval_deg[0], v.gamma_interval_deg[1],
                v.beta_interval_deg[0], v.beta_interval_deg[1]);
  std::printf("    profile %d points, %.1f s\n", r.profile_points, r.profile_wall_s);
}

// Wear `index` of Table 2, one case per fit (each case makes its own records under its own
// name, so ctest can run them in parallel; the noise seeds are the same in every case):
// the record at e = 0.1 alone within targets; alone at e = 0.7 within targets when reported
// identified, else the truth inside the reported intervals; both together within targets.
wi::JournalMeasurement record(int index, double ecc, const char* tag) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const int seed = 71 + 2 * index + (ecc > 0.4 ? 1 : 0);
  return wi::measure_journal(host::load_event(fd_record(k_wears[index], ecc, seed, tag)), b);
}

void check_e01(int index) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const Wear& w = k_wears[index];
  const wi::WearIdResult r01 = wi::identify_wear(b, record(index, 0.1, "alone"), options());
  print("e 0.1", w, r01);
  print_valleys(r01);
  expect_ranked_by_chi2(r01);
  EXPECT_TRUE(within(w, r01)) << w.tag;
  EXPECT_TRUE(r01.grid_converged);
}

void check_e07(int index) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const Wear& w = k_wears[index];
  const wi::JournalMeasurement m07 = record(index, 0.7, "alone");
  // e = 0.7 alone (with the journal pressed into the bore a wear may not be identifiable from
  // this record alone, docs/journal-bearing.md): an identified result must be within the
  // targets; a result reported not identifiable must hold the truth in its intervals.
  const wi::WearIdResult r07 = wi::identify_wear(b, m07, options());
  print("e 0.7", w, r07);
  print_valleys(r07);
  const double truth_cost = print_truth_chi2(b, {m07}, w, r07);
  expect_ranked_by_chi2(r07);
  // A complete search (issue 33, fifth round): some valley's cost, on the result's refined grid,
  // is no higher than the truth's (the polishes minimise that cost over the whole box; the
  // identification is never told the truth, this test is). Before the second global stage,
  // wear 3's best valley had 9.3e-6 against the truth's 1.14e-6.
  double lowest = INFINITY;
  for (const wi::WearValley& v : r07.valleys) lowest = std::min(lowest, v.cost);
  EXPECT_LE(lowest, truth_cost * 1.01) << w.tag << ": the search missed a valley lower than the truth's cost";
  // The reported intervals are the hull of the acceptable valleys' profile intervals; whether
  // the truth also lies in one valley's own region is printed (docs/journal-bearing.md).
  std::printf("  e = 0.7 %s: truth in the reported intervals %d, in one acceptable valley's region %d\n", w.tag,
              truth_in_reported_intervals(w, r07), truth_in_an_acceptable_valley(w, r07));
  if (r07.identified)
    EXPECT_TRUE(within(w, r07)) << w.tag << ": reported identified but outside the targets";
  else {
    EXPECT_TRUE(truth_in_reported_intervals(w, r07)) << w.tag << ": reported not identifiable, truth outside its intervals";
    // Issue 33, third round: the intervals come from profiles through acceptable points, so the
    // truth lies in one acceptable valley's own region, not only in the hull of several.
    EXPECT_TRUE(truth_in_an_acceptable_valley(w, r07)) << w.tag << ": truth only in the hull of the valleys' regions";
  }
}

void check_joint(int index) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const Wear& w = k_wears[index];
  const wi::JournalMeasurement m01 = record(index, 0.1, "joint"), m07 = record(index, 0.7, "joint");
  const wi::WearIdResult rj = wi::identify_wear(b, std::vector<wi::JournalMeasurement>{m07, m01}, options());
  print("joint", w, rj);
  print_valleys(rj);
  expect_ranked_by_chi2(rj);
  EXPECT_TRUE(within(w, rj)) << w.tag;
}
}  // namespace

TEST(JournalWearIdIndependent, Wear1AtE01Alone) { check_e01(0); }
TEST(JournalWearIdIndependent, Wear2AtE01Alone) { check_e01(1); }
TEST(JournalWearIdIndependent, Wear3AtE01Alone) { check_e01(2); }
TEST(JournalWearIdIndependent, Wear1AtE07Alone) { check_e07(0); }
TEST(JournalWearIdIndependent, Wear2AtE07Alone) { check_e07(1); }
TEST(JournalWearIdIndependent, Wear3AtE07Alone) { check_e07(2); }
TEST(JournalWearIdIndependent, Wear1Joint) { check_joint(0); }
TEST(JournalWearIdIndependent, Wear2Joint) { check_joint(1); }
TEST(JournalWearIdIndependent, Wear3Joint) { check_joint(2); }

TEST(JournalWearIdIndependent, UnwornRecordsHaveNoMeasurableWear) {
  // Unworn bore, FD-film records at both eccentricities: the model comparison (residual
  // loop's criterion) must say "no measurable wear".
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const Wear none{"unworn", "unworn", 0.0, 0.0, 0.0};
  int seed = 91;
  for (double ecc : {0.1, 0.7}) {
    const std::string dir = std::string(test::artefact_dir()) + "/journal_wear_fd";
    std::filesystem::create_directories(dir);
    const std::string stem = dir + "/unworn_e" + std::to_string(static_cast<int>(std::lround(ecc * 10)));
    wi::JournalSilOptions o;
    o.eccentricity = ecc;
    o.noise_seed = static_cast<std::uint64_t>(seed++);
    o.film = [g = b.journal.geometry](const mj::JournalState& s, double spin) {
      amb::test::journal::FdFilm f(g, {}, 288, 48);
      return f.coefficients(s, spin);
    };
    ASSERT_TRUE(wi::record_journal_sil(o, stem).ok);
    const wi::JournalMeasurement m = wi::measure_journal(host::load_event(stem + ".json"), b);
    const wi::WearIdResult r = wi::identify_wear(b, m, options());
    print_valleys(r);
    std::printf("unworn e %.1f: fit d0 %.2f um gamma %.2f beta %.2f, cost %.2e (unworn %.2e), dBIC %.1f, effect %.1f sigma, "
                "identified %d, measurable %d: %s\n",
                ecc, r.d0_um, r.gamma_deg, r.beta_deg, r.cost, r.unworn_cost, r.delta_bic, r.effect_sigma, r.identified,
                r.wear_measurable, r.decision_reason.c_str());
    EXPECT_FALSE(r.wear_measurable) << "e " << ecc;
    (void)none;
  }
}

