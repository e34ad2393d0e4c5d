// The fleet store on PostgreSQL (libpq): the test starts its own server from the installed
// Debian binaries (initdb + pg_ctl) in a temporary directory, as a non-root user (when run as
// root, the unprivileged user "nobody": PostgreSQL refuses to run as root), on a Unix socket
// only; imports the same 100 events, wear records and results as the SQLite test and
// demands identical answers to every query; stops the server and removes it.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "host-tools/core/fleet/fleet_schema.hpp"
#include "host-tools/core/fleet/fleet_store.hpp"
#include "tests/fleet/fleet_fixture.hpp"
#include "tests/support/read_text.hpp"

namespace fl = amb::host::fleet;
namespace tf = amb::test::fleet;
namespace fs = std::filesystem;

namespace {

/// Directory of the newest installed PostgreSQL server binaries, or "".
std::string pg_bin() {
  std::string best;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/usr/lib/postgresql", ec))
    if (fs::exists(e.path() / "bin" / "initdb") && (best.empty() || e.path().string() > best)) best = e.path().string();
  return best.empty() ? "" : best + "/bin";
}

/// A PostgreSQL server of its own in `dir`, stopped and removed by the destructor.
class LocalPostgres {
 public:
  explicit LocalPostgres(const fs::path& dir) : dir_(dir) {
    bin_ = pg_bin();
    if (bin_.empty()) return;
    port_ = 50000 + static_cast<int>(::getpid() % 10000);  // apart from the Slurm test's 30000-47998
    // As root, run the server as "nobody" (it refuses root); the directory must be theirs.
    if (::geteuid() == 0) {
      as_ = "runuser -u nobody -- ";
      fs::permissions(dir_, fs::perms::all);
      if (std::system(("chown nobody '" + dir_.string() + "'").c_str()) != 0) return;
    }
    const fs::path data = dir_ / "data";
    if (run(as_ + bin_ + "/initdb -A trust -U fleet -E UTF8 --no-sync -D '" + data.string() + "'", "initdb.log") != 0) return;
    const std::string opts = "-k '" + dir_.string() + "' -p " + std::to_string(port_) + " -c listen_addresses='' -c fsync=off";
    if (run(as_ + bin_ + "/pg_ctl -w -t 120 -D '" + data.string() + "' -l '" + (dir_ / "server.log").string() + "' -o \"" + opts +
                "\" start",
            "pg_ctl.log") != 0)
      return;
    started_ = true;
  }
  ~LocalPostgres() {
    if (started_) run(as_ + bin_ + "/pg_ctl -w -D '" + (dir_ / "data").string() + "' -m immediate stop", "stop.log");
  }
  bool started() const { return started_; }
  std::string why() const { return bin_.empty() ? "no PostgreSQL server under /usr/lib/postgresql" : log_; }
  std::string conninfo(const std::string& db) const {
    return "host=" + dir_.string() + " port=" + std::to_string(port_) + " user=fleet dbname=" + db;
  }
  int run(const std::string& cmd, const std::string& log) {
    const fs::path lp = dir_ / log;
    const int rc = std::system((cmd + " > '" + lp.string() + "' 2>&1").c_str());
    if (rc != 0) log_ += cmd + ":\n" + amb::test::read_text(lp) + amb::test::read_text(dir_ / "server.log");
    return rc;
  }

 private:
  fs::path dir_;
  std::string bin_, as_, log_;
  int port_ = 0;
  bool started_ = false;
};

}  // namespace

TEST(FleetPostgres, SameAnswersAsSqlite) {
  const fs::path dir = tf::fresh_dir("pg");
  const tf::FleetFiles files = tf::make_fleet_files(dir / "files", 2000);
  const fs::path server_dir = dir / "server";
  fs::create_directories(server_dir);
  {
  LocalPostgres pg(server_dir);  // stopped at the end of this block, before the directory goes
  if (pg_bin().empty()) GTEST_SKIP() << pg.why() << ": install the Debian package postgresql";
  ASSERT_TRUE(pg.started()) << pg.why();
  {
    auto admin = fl::open_database("postgres:" + pg.conninfo("postgres"));
    admin->script("CREATE DATABASE fleet_test");
  }
  fl::FleetStore sq((dir / "fleet.sqlite").string());
  fl::FleetStore pq("postgres:" + pg.conninfo("fleet_test"));
  EXPECT_EQ(pq.db().engine(), "postgresql");
  EXPECT_EQ(fl::schema_version(pq.db()), fl::k_schema_version);
  int added_sq = 0, added_pq = 0;
  for (const auto& f : files.all()) {
    added_sq += sq.add_file(f).added;
    added_pq += pq.add_file(f).added;
  }
  EXPECT_EQ(added_pq, 116);
  EXPECT_EQ(added_sq, added_pq);
  // Again: a no-op on both.
  for (const auto& f : files.events) EXPECT_FALSE(pq.add_file(f).added);
  EXPECT_EQ(pq.count("events"), 100);
  const std::string a = tf::query_dump(sq), b = tf::query_dump(pq);
  EXPECT_GT(std::count(a.begin(), a.end(), '\n'), 300);
  EXPECT_EQ(a, b);
  // The stored event bytes come back identical (bytea vs blob).
  const auto ra = sq.db().query("SELECT bytes FROM events ORDER BY content_hash LIMIT 1");
  const auto rb = pq.db().query("SELECT bytes FROM events ORDER BY content_hash LIMIT 1");
  ASSERT_EQ(ra.size(), 1u);
  ASSERT_EQ(rb.size(), 1u);
  EXPECT_EQ(std::get<fl::Blob>(ra[0][0]).bytes, std::get<fl::Blob>(rb[0][0]).bytes);
  // A failed statement inside an import leaves nothing behind (transaction rolled back).
  EXPECT_THROW(pq.db().query("SELECT no_such_column FROM events"), fl::DbError);
  EXPECT_EQ(tf::query_dump(pq), b);
  }
  fs::remove_all(dir);
}
