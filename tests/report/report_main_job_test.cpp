// The main job's report (amb-host scenario, as scripts/main-job.sh runs it) agrees with itself
// in the DOM (report_dom_check.hpp): the three peak contact forces (board quick-look, fitted
// drop model, simulated plant) each once with one value, the cause chain from the cut to the
// safe state, nothing clipped. About a minute: label long.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/cli/cli_run.hpp"
#include "tests/report/report_dom_check.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fs = std::filesystem;

TEST(ReportMainJob, TheMainJobsReportAgreesWithItself) {
  if (!fs::exists(amb::test::chromium::k_binary)) GTEST_SKIP() << "no Chromium (Debian package chromium)";
  const fs::path dir = fs::absolute(amb::test::artefact_dir()) / "report_main_job";
  fs::remove_all(dir);
  fs::create_directories(dir / "run");
  const amb::test::CliRun r = amb::test::run_cli(AMB_HOST_EXE, {"scenario", "--out", (dir / "out").string(), "--json", "--quiet"},
                                                 dir / "run", 800.0);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json s = nlohmann::json::parse(r.out);
  const fs::path page = s["report"].get<std::string>();
  ASSERT_TRUE(fs::exists(page)) << page;
  const nlohmann::json c = amb::test::check_report_dom(page, dir);
  amb::test::expect_consistent_report(c, {"board quick-look", "fitted drop model (wear record)", "simulated plant (SIL truth)"});
  const std::string chain = c["cause_chain"];
  for (const char* step : {"cut", "Phase A trigger", "fault latched", "safe state"})
    EXPECT_NE(chain.find(step), std::string::npos) << chain;
  // The aux-plane orbit: the rigid extrapolation, the plant's and the error between them.
  for (const char* b : {"A", "B"})
    for (const std::string& name : {std::string("rigid-extrapolation error ") + b + " at the aux-bearing plane",
                                    std::string("largest orbit radius ") + b + " at the aux-bearing plane, simulated plant (SIL truth)"})
      EXPECT_TRUE(c["figures"].contains(name)) << name;
  // The figures the scenario prints are the ones on the page.
  char peak[32];
  std::snprintf(peak, sizeof peak, "%.0f N", s["max_contact_force_n"].get<double>());
  EXPECT_EQ(c["figures"]["peak contact force, simulated plant (SIL truth)"], nlohmann::json::array({peak}));
}

}  // namespace
