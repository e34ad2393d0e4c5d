// The report of a drop that this project did not make (issue 36): each shared synthetic drop
// (../shared/data/synthetic, an independent simulator's amb-measured-event/1 files) taken
// through the command line as a user would - import, fit with a wear record, report with the
// fit and the wear record - must agree with itself in the DOM (report_dom_check.hpp: one
// value per figure, the peak force named by its definition, nothing clipped, log plots with
// ticks) and with what `amb-host fit --json` printed for the same event. Two fits per drop
// (about 30 s each on a loaded 2-core machine): label long, with the main job's report.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "tests/cli/cli_run.hpp"
#include "tests/report/report_dom_check.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fs = std::filesystem;

// A figure quoted as "0.388 s" against a number: equal to the quoted resolution.
void expect_quoted(const nlohmann::json& values, double want_s, const std::string& name) {
  ASSERT_EQ(values.size(), 1u) << name << ": " << values.dump();
  const double got = std::stod(values[0].get<std::string>());
  EXPECT_NEAR(got, want_s, 0.0005 + 1e-9) << name << ": the page says " << values[0] << ", amb-host fit " << want_s;
}

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

class ReportMeasured : public ::testing::TestWithParam<int> {};

TEST_P(ReportMeasured, ASharedSyntheticDropsReportAgreesWithItselfAndWithTheFit) {
  if (!fs::exists(amb::test::chromium::k_binary)) GTEST_SKIP() << "no Chromium (Debian package chromium)";
  const std::string stem = "bath_drop_example_" + std::to_string(GetParam());
  const fs::path event = fs::path(amb::test::shared_dir()) / "data" / "synthetic" / (stem + ".json");
  ASSERT_TRUE(fs::exists(event)) << event;
  const fs::path dir = fs::absolute(amb::test::artefact_dir()) / ("report_" + stem);
  fs::remove_all(dir);
  fs::create_directories(dir / "run");
  const auto run = [&](const std::vector<std::string>& args) {
    const amb::test::CliRun r = amb::test::run_cli(AMB_HOST_EXE, args, dir / "run", 600.0);
    EXPECT_EQ(r.exit_code, 0) << amb::test::shown(args) << "\n" << r.err;
    return r;
  };

  const auto imported = run({"import", event.string(), "--json"});
  ASSERT_EQ(imported.exit_code, 0);
  const fs::path wear = dir / "wear.ambw";
  const auto fitted = run({"fit", event.string(), "--wear-out", wear.string(), "--json", "--quiet"});
  ASSERT_EQ(fitted.exit_code, 0);
  const nlohmann::json f = nlohmann::json::parse(fitted.out);
  const fs::path page = dir / (stem + ".html");
  const auto reported = run({"report", event.string(), "--fit", "--wear", wear.string(), "--out", page.string(), "--json", "--quiet"});
  ASSERT_EQ(reported.exit_code, 0);
  const nlohmann::json rj = nlohmann::json::parse(reported.out);
  for (const char* s : {"orbit", "rubbing", "speed", "forces", "load", "fit", "wear"})
    EXPECT_TRUE(rj["sections"][s]["available"].get<bool>()) << s << ": " << rj["sections"][s].dump();
  EXPECT_FALSE(rj["sections"]["replay"]["available"].get<bool>()) << "a measured event has nothing to replay";

  const nlohmann::json c = amb::test::check_report_dom(page, dir / "dom");
  amb::test::expect_consistent_report(c, {"fitted drop model (wear record)"});
  const auto& fig = c["figures"];
  // The fit on the page is the fit the user ran: friction and rubbing times as amb-host fit printed them.
  EXPECT_EQ(fig["friction coefficient"], nlohmann::json::array({fmt("%.4f", f["friction_coefficient"].get<double>())}));
  EXPECT_EQ(fig["last friction coefficient"], nlohmann::json::array({fmt("%.4f", f["friction_coefficient"].get<double>())}));
  const char* ab[2] = {"A", "B"};
  for (size_t b = 0; b < 2; ++b)
    for (const auto& [state, key] : {std::pair<std::string, std::string>{"swinging", "swing"}, {"forward rub", "forward"}, {"backward rub", "backward"}}) {
      const std::string fit_name = state + " " + ab[b] + ", fitted drop model (fit window)";
      const std::string meas_name = state + " " + ab[b] + ", measured orbit (fit window)";
      expect_quoted(fig[fit_name], f["rubbing_s_per_bearing"][b][key].get<double>(), fit_name);
      expect_quoted(fig[meas_name], f["measured_rubbing_s_per_bearing"][b][key].get<double>(), meas_name);
      // The wear record holds this one event: its sums are the fitted times, quoted the same.
      EXPECT_EQ(fig[state + " " + ab[b] + ", wear record (all events)"], fig[fit_name]) << state << " " << ab[b];
    }
  // The event's facts come from the file: the declared fault and the recorded speed.
  EXPECT_EQ(fig["declared faults"], nlohmann::json::array({"amb_cutoff_all"}));
  EXPECT_NE(c["cause_chain"].get<std::string>().find("amb_cutoff_all"), std::string::npos) << c["cause_chain"];
  std::printf("[report] %s: friction %.4f, page %s\n", stem.c_str(), f["friction_coefficient"].get<double>(), page.c_str());
}

INSTANTIATE_TEST_SUITE_P(SharedSyntheticDrops, ReportMeasured, ::testing::Values(1, 2, 3, 4));

}  // namespace
