// Issue 33: the false-alarm rate of wear-id's "no measurable wear" decision, measured on
// unworn records made by the independent finite-difference film (fd_film.hpp, 288 x 48), not by
// the production film the identification uses. Each record goes through identify_wear with the
// options `amb-host wear-id --model 3p` uses by default (film grid refined to 0.2 %); the
// decision is the residual loop's criterion (engine::decide, default settings), not tuned here.
// A false alarm: a wear declared measurable on an unworn bore.
//
// Population (label long, JournalWearIdFalseAlarm.Population): 32 records, static eccentricity
// 0.1 ... 0.8 (the bearing's load rises with it), speeds 30 / 34 / 38 Hz and a second noise seed
// at 34 Hz. Asserted: the rate <= 5 % (the residual loop's clean-population limit,
// docs/residual.md); the rate and its Wilson 95 % interval are printed.
// Small version (default set, JournalWearIdFalseAlarm.TwoUnwornRecords): two of those settings.
// JournalWearIdFalseAlarm.FilmErrorIsNotWear (long): the record that showed the film's error
// taken for wear (issue 33, sixth round).
// Run: build/tests/journal/journal_wear_id_false_alarm_tests
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "fd_film.hpp"
#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/wearid/journal_sil_record.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;

namespace {
struct Setting {
  double eccentricity;
  double speed_hz;
  int noise_seed;
};

// The population: eccentricity 0.1..0.8 at 30, 34 and 38 Hz, and 34 Hz with a second seed.
std::vector<Setting> population() {
  std::vector<Setting> s;
  const double speeds[] = {30.0, 34.0, 38.0, 34.0};
  for (int block = 0; block < 4; ++block)
    for (int k = 0; k < 8; ++k) s.push_back({0.1 * (k + 1), speeds[block], 500 + 8 * block + k});
  return s;
}

// Wilson score interval for k of n at 95 %.
std::pair<double, double> wilson(int k, int n) {
  const double z = 1.959964, p = static_cast<double>(k) / n, z2 = z * z;
  const double den = 1 + z2 / n, mid = (p + z2 / (2 * n)) / den;
  const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n)) / den;
  return {std::max(0.0, mid - half), std::min(1.0, mid + half)};
}

// One unworn FD-film record, identified; returns whether a wear was declared. `ok` false when
// the record could not be made.
bool declared(const board::BoardConfig& b, const Setting& s, const char* tag, bool& ok) {
  const std::string dir = std::string(test::artefact_dir()) + "/journal_false_alarm";
  std::filesystem::create_directories(dir);
  const std::string stem = dir + "/" + tag + "_" + std::to_string(s.noise_seed);
  wi::JournalSilOptions o;
  o.eccentricity = s.eccentricity;
  o.speed_hz = s.speed_hz;
  o.noise_seed = static_cast<std::uint64_t>(s.noise_seed);
  o.film = [g = b.journal.geometry](const mj::JournalState& st, double spin) {
    amb::test::journal::FdFilm f(g, {}, 288, 48);
    return f.coefficients(st, spin);
  };
  const auto t0 = std::chrono::steady_clock::now();
  const wi::JournalSilSummary sum = wi::record_journal_sil(o, stem);
  ok = sum.ok;
  if (!ok) {
    ADD_FAILURE() << "record e " << s.eccentricity << " " << s.speed_hz << " Hz: " << sum.message;
    return false;
  }
  const wi::JournalMeasurement m = wi::measure_journal(host::load_event(stem + ".json"), b);
  wi::WearIdOptions io;
  io.model = mj::WearModel::elliptical;
  io.grid_tolerance = 2e-3;
  const wi::WearIdResult r = wi::identify_wear(b, m, io);
  std::printf("e %.1f %.0f Hz seed %d: fit %.2f um / %.2f / %.2f deg, identified %d, dBIC %.1f, effect %.1f sigma: %s "
              "(%s) %.0f s\n",
              s.eccentricity, s.speed_hz, s.noise_seed, r.d0_um, r.gamma_deg, r.beta_deg, r.identified, r.delta_bic,
              r.effect_sigma, r.wear_measurable ? "WEAR DECLARED" : "no measurable wear", r.decision_reason.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  std::fflush(stdout);
  return r.wear_measurable;
}
}  // namespace

TEST(JournalWearIdFalseAlarm, TwoUnwornRecords) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const std::vector<Setting> pop = population();
  for (const Setting& s : {pop[2], pop[29]}) {  // e 0.3 at 30 Hz, e 0.6 at 34 Hz (second seed)
    bool ok = false;
    EXPECT_FALSE(declared(b, s, "small", ok)) << "e " << s.eccentricity << " " << s.speed_hz << " Hz";
  }
}

// The unworn record on which the fifth round's search (a second global stage) found a wear of
// 29.8 um that bought a BIC decrease of 14.6 against the probe noise alone: a film moved by
// about its own discretisation error (0.2 % in K/C). Weighed with the verdict's chi-square
// (noise and the film's K/C error), that decrease is -3.6 (issue 33, sixth round). Long: ~50 s.
TEST(JournalWearIdFalseAlarm, FilmErrorIsNotWear) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const Setting s = population()[6];  // e 0.7 at 30 Hz, seed 506
  bool ok = false;
  EXPECT_FALSE(declared(b, s, "film_error", ok));
  EXPECT_TRUE(ok);
}

TEST(JournalWearIdFalseAlarm, Population) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  int n = 0, alarms = 0;
  for (const Setting& s : population()) {
    bool ok = false;
    const bool d = declared(b, s, "pop", ok);
    if (!ok) continue;
    ++n;
    alarms += d ? 1 : 0;
  }
  ASSERT_GE(n, 30);
  const auto [lo, hi] = wilson(alarms, n);
  std::printf("false alarms: %d of %d unworn records, rate %.1f %% (Wilson 95 %%: %.1f-%.1f %%)\n", alarms, n,
              100.0 * alarms / n, 100.0 * lo, 100.0 * hi);
  EXPECT_LE(static_cast<double>(alarms) / n, 0.05);
}
