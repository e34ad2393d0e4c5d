// The fleet store on SQLite: 100 events from 5 simulated boards, wear records, fit and
// residual results; importing again is a no-op; a bad file is refused without writing; a
// store of schema v1 is migrated; an import killed mid-way (SIGKILL of a child process)
// leaves the store consistent and a re-import completes it; trend and nearest-budget.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "host-tools/core/fleet/fleet_report.hpp"
#include "host-tools/core/fleet/fleet_schema.hpp"
#include "host-tools/core/fleet/fleet_store.hpp"
#include "tests/fleet/fleet_fixture.hpp"

namespace fl = amb::host::fleet;
namespace tf = amb::test::fleet;
namespace fs = std::filesystem;

TEST(FleetSqlite, ImportsOnceAndAnswersQueries) {
  const fs::path dir = tf::fresh_dir("sqlite");
  const tf::FleetFiles files = tf::make_fleet_files(dir / "files");
  fl::FleetStore store((dir / "fleet.sqlite").string());
  EXPECT_EQ(fl::schema_version(store.db()), fl::k_schema_version);
  int added = 0;
  for (const auto& f : files.all()) added += store.add_file(f).added;
  EXPECT_EQ(added, 100 + 12 + 4);
  EXPECT_EQ(store.count("events"), 100);
  EXPECT_EQ(store.count("event_bearings"), 200);
  EXPECT_EQ(store.count("wear_records"), 12);
  EXPECT_EQ(store.count("results"), 4);
  EXPECT_EQ(store.count("machines"), 5);
  const std::string before = tf::query_dump(store);

  // Same files again (and a copy of an event under another name): nothing added.
  for (const auto& f : files.all()) EXPECT_FALSE(store.add_file(f).added) << f;
  fs::copy_file(files.events[7], dir / "copy.ambe");
  const fl::AddResult copy = store.add_file((dir / "copy.ambe").string());
  EXPECT_FALSE(copy.added);
  EXPECT_EQ(copy.kind, "event");
  EXPECT_EQ(store.count("events"), 100);
  EXPECT_EQ(tf::query_dump(store), before);

  // A corrupted event is refused naming the file and the problem; nothing is written.
  {
    std::fstream f(files.events[3], std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x5a');
  }
  fs::copy_file(files.events[3], dir / "bad.ambe");
  try {
    store.add_file((dir / "bad.ambe").string());
    FAIL() << "corrupted event accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ambe"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "other.json") << "{\"cases\": 3}";
  EXPECT_THROW(store.add_file((dir / "other.json").string()), std::invalid_argument);
  EXPECT_THROW(store.add_file((dir / "missing.ambe").string()), std::invalid_argument);
  EXPECT_EQ(tf::query_dump(store), before);

  // Machines, trend, nearest budget.
  const auto ms = store.machines();
  ASSERT_EQ(ms.size(), 5u);
  for (const auto& m : ms) {
    EXPECT_EQ(m.events, 20) << m.name;
    EXPECT_EQ(m.last_event_number, 20);
  }
  EXPECT_EQ(ms[0].wear_records, 4);
  EXPECT_EQ(ms[4].wear_records, 0);
  EXPECT_EQ(ms[0].fits, 1);
  EXPECT_EQ(ms[0].residuals, 1);
  const auto trend = store.trend("board-2");
  size_t wear_points = 0;
  double last = -1.0;
  for (const auto& p : trend) {
    ASSERT_EQ(p.machine, "board-2");
    if (p.source == "wear" && p.bearing == 1) {
      ++wear_points;
      EXPECT_GT(p.life_used_fraction, last);  // cumulative: grows with the sequence
      last = p.life_used_fraction;
    }
  }
  EXPECT_EQ(wear_points, 4u);
  const auto nearest = store.nearest_budget();
  ASSERT_EQ(nearest.size(), 10u);  // 5 machines x 2 bearings
  for (size_t i = 1; i < nearest.size(); ++i) EXPECT_GE(nearest[i - 1].life_used_fraction, nearest[i].life_used_fraction);
  // board-3 aux 2 has the largest wear-record life: 1500 * 4 * 3 * 2 / 20000 = 1.8.
  EXPECT_EQ(nearest[0].machine, "board-3");
  EXPECT_EQ(nearest[0].bearing, 1);
  EXPECT_EQ(nearest[0].source, "wear");
  EXPECT_NEAR(nearest[0].life_used_fraction, 1.8, 1e-6);
  // Boards 4 and 5 have no wear record: the quick-look sum over their valid events.
  for (const auto& s : nearest)
    if (s.machine == "board-5") {
      EXPECT_EQ(s.source, "quick_look");
      EXPECT_EQ(s.events, 20);
      EXPECT_GT(s.life_used_fraction, 0.0);
    }
  const std::string page = fl::render_fleet_page({"test", store.machines(), nearest, store.trend()});
  EXPECT_NE(page.find("id=\"nearest\""), std::string::npos);
  EXPECT_NE(page.find("<svg id=\"trend\""), std::string::npos);
  EXPECT_NE(page.find("id=\"machines\""), std::string::npos);
  fs::remove_all(dir);
}

TEST(FleetSqlite, MigratesAVersion1Store) {
  const fs::path dir = tf::fresh_dir("migrate");
  const tf::FleetFiles files = tf::make_fleet_files(dir / "files", 200);
  const std::string path = (dir / "fleet.sqlite").string();
  {
    auto db = fl::open_database(path);
    fl::migrate(*db, 1);
    EXPECT_EQ(fl::schema_version(*db), 1);
    EXPECT_TRUE(db->query("SELECT name FROM sqlite_master WHERE type = 'index' AND name = 'events_machine'").empty());
  }
  {
    fl::FleetStore store(path);  // opening migrates
    EXPECT_EQ(fl::schema_version(store.db()), 2);
    EXPECT_EQ(store.db().query("SELECT name FROM sqlite_master WHERE type = 'index' AND name = 'events_machine'").size(), 1u);
    for (const auto& f : files.events) store.add_file(f);
    EXPECT_EQ(store.count("events"), 100);
  }
  {
    auto db = fl::open_database(path);
    db->query("UPDATE schema_version SET version = 99");
  }
  EXPECT_THROW(fl::FleetStore store(path), fl::DbError);  // a newer store is refused, not downgraded
  fs::remove_all(dir);
}

TEST(FleetSqlite, KilledImportLeavesTheStoreConsistent) {
  const fs::path dir = tf::fresh_dir("kill");
  // Large events (0.8 MB of samples each) so that an import takes long enough to be killed in it.
  const tf::FleetFiles files = tf::make_fleet_files(dir / "files", 10000);
  int kills_mid_import = 0;
  for (int round = 0; round < 3 && kills_mid_import == 0; ++round) {
    const std::string path = (dir / ("fleet-" + std::to_string(round) + ".sqlite")).string();
    { fl::FleetStore init(path); }  // schema in place before the child starts
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      try {
        fl::FleetStore store(path);
        for (const auto& f : files.events) store.add_file(f);
      } catch (...) {
        ::_exit(3);
      }
      ::_exit(0);
    }
    // Kill it once a few events are in (and while it is still importing).
    const std::int64_t kill_at = 3 + 4 * round;
    {
      fl::FleetStore watch(path);
      const auto t0 = std::chrono::steady_clock::now();
      while (watch.count("events") < kill_at && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120))
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    const bool killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
    kills_mid_import += killed;

    fl::FleetStore store(path);
    const auto integrity = store.db().query("PRAGMA integrity_check");
    ASSERT_EQ(fl::as_text(integrity.at(0).at(0)), "ok");
    const std::int64_t n = store.count("events");
    EXPECT_GE(n, kill_at);
    if (killed) {
      EXPECT_LT(n, 100);
    }
    // Every stored event is whole: exactly two bearing rows, no orphans.
    EXPECT_EQ(fl::as_int(store.db().query("SELECT COUNT(*) FROM events e WHERE (SELECT COUNT(*) FROM event_bearings b"
                                          " WHERE b.event_id = e.id) <> 2")[0][0]),
              0);
    EXPECT_EQ(store.count("event_bearings"), 2 * n);
    EXPECT_EQ(fl::as_int(store.db().query("SELECT COUNT(*) FROM event_bearings b WHERE NOT EXISTS"
                                          " (SELECT 1 FROM events e WHERE e.id = b.event_id)")[0][0]),
              0);
    // Re-import completes the store: only the missing events are added.
    int added = 0;
    for (const auto& f : files.events) added += store.add_file(f).added;
    EXPECT_EQ(added, 100 - n);
    EXPECT_EQ(store.count("events"), 100);
    std::printf("[fleet] round %d: child %s after %lld events; re-import added %d\n", round,
                killed ? "killed" : "had finished", static_cast<long long>(n), added);
  }
  EXPECT_GE(kills_mid_import, 1) << "the import always finished before the kill";
  fs::remove_all(dir);
}
