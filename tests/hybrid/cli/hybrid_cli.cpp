// amb-host hybrid on the command line: train on the four CWRU 1797 rpm records with and without
// the kinematic-transport inputs, predict the outer race at the held-back 1750 rpm / 2 hp and
// score it. stdout is JSON alone; the transport switches reach the model (with them the hybrid
// is not the 8-DOF-only map, without them it is); the ablations are printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/run_json_cli.hpp"
#include "tests/support/test_paths.hpp"

namespace fs = std::filesystem;

namespace {

/// Run amb-host with `args`; stdout parsed as JSON into `out`. Returns the exit code.
int amb_host(const fs::path& dir, const std::string& args, nlohmann::json& out, std::string& err) {
  return amb::test::run_json_cli(std::string(AMB_HOST_EXE) + " " + args, dir, out, err);
}

std::string records() {
  const std::string d = std::string(amb::test::shared_dir()) + "/data/measured/cwru/";
  std::string r;
  for (const char* f : {"1797_Normal.mat,state=healthy", "1797_IR_7_DE12.mat,state=inner_race", "1797_ORat6_7_DE12.mat,state=outer_race",
                        "1797_B_7_DE12.mat,state=ball"})
    r += " --record '" + d + f + ",rpm=1797,load=0'";
  return r;
}

}  // namespace

TEST(HybridCli, TransportSwitchesReachTheModelAndTheAblationsArePrinted) {
  const fs::path dir = fs::temp_directory_path() / "amb_hybrid_cli";
  fs::create_directories(dir);
  const std::string measured = std::string(amb::test::shared_dir()) + "/data/measured/cwru/1750_ORat6_7_DE12.mat";
  nlohmann::json j;
  std::string err;
  for (const bool transport : {false, true}) {
    const fs::path model = dir / (transport ? "with.json" : "without.json");
    ASSERT_EQ(amb_host(dir, "hybrid train --json --out '" + model.string() + "'" + records() + (transport ? " --transport-env --transport-log-psd" : ""), j, err), 0) << err;
    ASSERT_EQ(amb_host(dir, "hybrid predict --json --model '" + model.string() + "' --state outer_race --rpm 1750 --load 2 --measured '" + measured + "'", j, err), 0) << err;
    ASSERT_TRUE(j.contains("ablations")) << j.dump();
    const double hybrid_env = j["pearson"]["hybrid"]["envelope_spectrum"], sim_env = j["ablations"]["hybrid_sim"]["envelope_spectrum"];
    const double hybrid_log = j["pearson"]["hybrid"]["log_spectrum"], sim_log = j["ablations"]["hybrid_sim"]["log_spectrum"];
    ASSERT_FALSE(j["ablations"]["transport"].is_null());
    std::printf("transport %d: hybrid log %.3f env %.3f, 8-DOF-only map log %.3f env %.3f, transport alone log %.3f env %.3f\n", transport,
                hybrid_log, hybrid_env, sim_log, sim_env, j["ablations"]["transport"]["log_spectrum"].get<double>(),
                j["ablations"]["transport"]["envelope_spectrum"].get<double>());
    if (transport) {
      EXPECT_GT(std::abs(hybrid_env - sim_env), 1e-3) << "the transport input did not reach the envelope map";
      EXPECT_GT(std::abs(hybrid_log - sim_log), 1e-3) << "the transport input did not reach the log-spectrum map";
    } else {
      EXPECT_DOUBLE_EQ(hybrid_env, sim_env);
      EXPECT_DOUBLE_EQ(hybrid_log, sim_log);
    }
  }
  fs::remove_all(dir);
}
