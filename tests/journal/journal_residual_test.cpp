// The residual loop's journal path (host-tools/core/residual/journal_residual.hpp) on SIL
// records of the UNICAMP journal-bearing rig: the board declares an unworn bore and is never
// told what the generator put into the plant.
//  - a record with seed 002's wear 1 (46.5 um / 23 deg / 77 deg) names journal_bearing_wear,
//    the spectral error falls by more than 90 % and the fitted wear is near the truth;
//  - a record with an unworn bearing gets no element.
// Label long (each case generates a 60 s SIL record and runs one identification).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/residual/journal_residual.hpp"
#include "host-tools/core/wearid/journal_sil_record.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;
namespace hr = amb::host::residual;

namespace {
std::string record(const char* name, const mj::WearParams& w, std::uint64_t seed) {
  const std::string dir = std::string(test::artefact_dir()) + "/journal_residual";
  std::filesystem::create_directories(dir);
  const std::string stem = dir + "/" + name;
  wi::JournalSilOptions o;
  o.eccentricity = 0.1;
  o.wear = w;
  o.noise_seed = seed;
  const wi::JournalSilSummary s = wi::record_journal_sil(o, stem);
  EXPECT_TRUE(s.ok) << s.message;
  return stem + ".json";
}
}  // namespace

TEST(JournalResidual, UndeclaredWearIsNamedAndTheErrorFalls) {
  constexpr double k_deg = M_PI / 180.0;
  const std::string path = record("worn_w1", {mj::WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg}, 31);
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  ASSERT_EQ(b.journal.wear.model, mj::WearModel::none);  // the board declares no wear
  const host::LoadedEvent ev = host::load_event(path);
  ASSERT_TRUE(hr::is_journal_event(ev, b));
  const hr::JournalResidualOutcome o = hr::run_journal_residual(ev, b);
  std::printf("[ RESULT ] worn: spectral error %.4g -> %.4g, dBIC %.1f, effect %.1f sigma, wear %.2f um / %.2f deg / %.2f deg (%.1f s)\n",
              o.before.spectral, o.after.spectral, o.delta_bic, o.effect_sigma, o.fit.d0_um, o.fit.gamma_deg, o.fit.beta_deg,
              o.fit.wall_s);
  EXPECT_EQ(o.verdict, "journal_bearing_wear");
  ASSERT_EQ(o.effects_added.size(), 1u);
  EXPECT_EQ(o.effects_added[0].name, "journal_bearing_wear");
  EXPECT_LT(o.after.spectral, 0.1 * o.before.spectral);
  EXPECT_NEAR(o.fit.d0_um, 46.5, 0.1 * 46.5);
  EXPECT_NEAR(o.fit.gamma_deg, 23.0, 3.0);
  EXPECT_NEAR(o.fit.beta_deg, 77.0, 0.1 * 77.0);
}

TEST(JournalResidual, UnwornBearingGetsNoElement) {
  const std::string path = record("unworn", {}, 32);
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  const host::LoadedEvent ev = host::load_event(path);
  ASSERT_TRUE(hr::is_journal_event(ev, b));
  const hr::JournalResidualOutcome o = hr::run_journal_residual(ev, b);
  std::printf("[ RESULT ] unworn: spectral error %.4g, candidate %.4g, dBIC %.1f, effect %.1f sigma, worst 1-sigma %.3g of range\n",
              o.before.spectral, 1.0 - o.relative_improvement, o.delta_bic, o.effect_sigma, o.worst_sigma_of_range);
  EXPECT_EQ(o.verdict, "none");
  EXPECT_TRUE(o.effects_added.empty());
  EXPECT_EQ(o.after.spectral, o.before.spectral);
}

TEST(JournalResidual, NonJournalRecordIsNotTakenByTheJournalPath) {
  // The AMB-only board has no [journal_bearing]: the steady loop keeps such records.
  const board::BoardConfig b = board::load_board("unicamp-amb-rig");
  host::LoadedEvent ev;
  std::string why;
  EXPECT_FALSE(hr::is_journal_event(ev, b, &why));
  EXPECT_NE(why.find("journal_bearing"), std::string::npos) << why;
}
