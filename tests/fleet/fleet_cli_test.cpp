// amb-host fleet on the command line: add (twice: the second adds nothing), a refused file
// (exit 1, named on stderr, nothing on stdout: bad input gives no output, docs/cli.md), list /
// trend / report --json.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/fleet/fleet_fixture.hpp"
#include "tests/support/read_text.hpp"
#include "tests/support/run_json_cli.hpp"

namespace tf = amb::test::fleet;
namespace fs = std::filesystem;

namespace {

/// Run amb-host fleet with `args`; stdout parsed as JSON into `out`. Returns the exit code.
int fleet(const fs::path& dir, const std::string& args, nlohmann::json& out, std::string& err) {
  return amb::test::run_json_cli(std::string(AMB_HOST_EXE) + " fleet --store '" + (dir / "cli.sqlite").string() + "' " + args, dir, out, err);
}

/// Run amb-host fleet with `args` where bad input is expected: returns the exit code; stdout's
/// text in `out`, stderr in `err`.
int fleet_refused(const fs::path& dir, const std::string& args, std::string& out, std::string& err) {
  const fs::path o = dir / "stdout", e = dir / "stderr";
  const std::string cmd = std::string(AMB_HOST_EXE) + " fleet --store '" + (dir / "cli.sqlite").string() + "' " + args + " > '" +
                          o.string() + "' 2> '" + e.string() + "'";
  const int rc = std::system(cmd.c_str());
  out = amb::test::read_text(o);
  err = amb::test::read_text(e);
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST(FleetCli, AddListTrendReport) {
  const fs::path dir = tf::fresh_dir("cli");
  tf::make_fleet_files(dir / "files", 200);
  // A JSON file of another kind in the directory is skipped (named on the command line it is refused).
  std::ofstream(dir / "files" / "scenario_summary.json") << "{\"speed_at_cut_hz\": 45.0}";
  nlohmann::json j;
  std::string err;
  ASSERT_EQ(fleet(dir, "add '" + (dir / "files").string() + "' --json", j, err), 0) << err;
  EXPECT_EQ(j["added"], 116);
  EXPECT_EQ(j["errors"], 0);
  EXPECT_EQ(j["skipped_json"], 1);
  std::string text;
  EXPECT_EQ(fleet_refused(dir, "add '" + (dir / "files" / "scenario_summary.json").string() + "' --json", text, err), 1);
  EXPECT_EQ(text, "") << "a refused file printed a summary";
  ASSERT_EQ(fleet(dir, "add '" + (dir / "files").string() + "' --json", j, err), 0) << err;
  EXPECT_EQ(j["added"], 0);
  EXPECT_EQ(j["already_stored"], 116);
  std::ofstream(dir / "junk.ambe") << "AMBE but not an event";
  EXPECT_EQ(fleet_refused(dir, "add '" + (dir / "junk.ambe").string() + "' --json", text, err), 1);
  EXPECT_EQ(text, "") << "a refused file printed a summary";
  EXPECT_NE(err.find("junk.ambe"), std::string::npos) << err;
  ASSERT_EQ(fleet(dir, "list --json", j, err), 0) << err;
  EXPECT_EQ(j["machines"].size(), 5u);
  EXPECT_EQ(j["schema_version"], 2);
  ASSERT_EQ(fleet(dir, "trend --machine board-1 --json", j, err), 0) << err;
  EXPECT_GT(j["trend"].size(), 8u);
  for (const auto& p : j["trend"]) EXPECT_EQ(p["machine"], "board-1");
  const fs::path page = dir / "page" / "fleet.html";
  ASSERT_EQ(fleet(dir, "report --out '" + page.string() + "' --json", j, err), 0) << err;
  EXPECT_EQ(j["nearest"].size(), 10u);
  EXPECT_EQ(j["nearest"][0]["machine"], "board-3");
  EXPECT_NE(amb::test::read_text(page).find("<svg id=\"trend\""), std::string::npos);
  fs::remove_all(dir);
}
