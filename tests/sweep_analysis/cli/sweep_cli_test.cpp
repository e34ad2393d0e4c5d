// amb-host sweep end to end (issue 35): the firmware sweeps its simulated rig, the event is
// written and decoded, the analysis rates each axis per ISO 14839-3 against the board's model
// and writes the page; the stored event feeds `amb-host residual` (the same engine) and
// `amb-host sweep --event`; a folder holding it is accepted by `fleet add` (the sweep skipped).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/run_json_cli.hpp"
#include "tests/support/test_paths.hpp"

namespace fs = std::filesystem;

namespace {
fs::path work_dir(const char* name) {
  const fs::path d = fs::temp_directory_path() / ("amb_sweep_cli_" + std::string(name) + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
std::string exe() { return AMB_HOST_EXE; }
}  // namespace

TEST(SweepCli, BathSweepIsRatedAgainstItsModelAndFeedsTheResidualLoop) {
  const fs::path dir = work_dir("bath");
  nlohmann::json j;
  std::string err;
  ASSERT_EQ(amb::test::run_json_cli(exe() + " sweep --board bath-amb-rig --out '" + dir.string() + "' --json", dir, j, err), 0) << err;
  ASSERT_TRUE(j.contains("analysis")) << j.dump();
  EXPECT_TRUE(j["acquired"].get<bool>());
  EXPECT_FALSE(j["aborted"].get<bool>());
  const auto& zones = j["analysis"]["zones"];
  ASSERT_EQ(zones.size(), 4u);  // every control axis of the default plan
  for (const auto& z : zones) {
    const double peak = z["peak"].get<double>(), model = z["model_peak"].get<double>();
    EXPECT_NEAR(peak, model, 0.05 * model) << z.dump();  // the 5 % band
    EXPECT_EQ(z["zone"].get<std::string>(), z["model_zone"].get<std::string>()) << z.dump();
    EXPECT_LE(z["band"][0].get<double>(), peak);
    EXPECT_GE(z["band"][1].get<double>(), peak);
  }
  EXPECT_EQ(j["analysis"]["residual"]["verdict"].get<std::string>(), "none");  // nothing injected
  ASSERT_TRUE(fs::exists(j["page"].get<std::string>()));
  const std::string event = j["event"].get<std::string>();

  // The stored event through the residual command: the same analysis, the same verdict.
  nlohmann::json r;
  ASSERT_EQ(amb::test::run_json_cli(exe() + " residual '" + event + "' --json --quiet", dir, r, err), 0) << err;
  EXPECT_EQ(r["residual"]["verdict"], j["analysis"]["residual"]["verdict"]);
  EXPECT_EQ(r["zones"].size(), 4u);

  // Re-rating the stored event without the loop gives the same zones.
  nlohmann::json e;
  ASSERT_EQ(amb::test::run_json_cli(exe() + " sweep --event '" + event + "' --no-residual --json --quiet --html '" +
                                        (dir / "again.html").string() + "'",
                                    dir, e, err),
            0)
      << err;
  EXPECT_FALSE(e["acquired"].get<bool>());
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(e["analysis"]["zones"][i]["peak"], zones[i]["peak"]);
    EXPECT_EQ(e["analysis"]["zones"][i]["zone"], zones[i]["zone"]);
  }

  // fleet add on the folder: the sweep event is skipped, not a refusal of the whole folder.
  nlohmann::json f;
  const int rc = amb::test::run_json_cli(exe() + " fleet --store '" + (dir / "fleet.sqlite").string() + "' add '" + dir.string() +
                                             "' --json",
                                         dir, f, err);
  EXPECT_EQ(rc, 0) << err;
  EXPECT_EQ(f["errors"].get<int>(), 0) << f.dump();
  EXPECT_GE(f["skipped_json"].get<int>(), 1) << f.dump();
}

TEST(SweepCli, AMissingOrForeignEventIsRefusedNamingTheOption) {
  const fs::path dir = work_dir("bad");
  for (const std::string& arg : {std::string("--event '") + dir.string() + "/none.ambe'", "--event '" + std::string(amb::test::source_dir()) + "/README.md'"}) {
    const fs::path e = dir / "stderr";
    const int rc = std::system((exe() + " sweep " + arg + " > /dev/null 2> '" + e.string() + "'").c_str());
    EXPECT_EQ(WEXITSTATUS(rc), 1) << arg;
    EXPECT_NE(amb::test::read_text(e).find("--event"), std::string::npos) << arg << ": " << amb::test::read_text(e);
  }
}
