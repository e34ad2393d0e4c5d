// The report agrees with itself (issue 36), checked in the DOM Chromium lays out
// (report_dom_check.hpp) on the report of a SIL drop with a fit and a wear record: each peak
// contact force once per definition and quoted with one value, the rubbing times named by
// window, no caption or legend outside its picture, tick values on log axes.
#include <gtest/gtest.h>

#include <filesystem>

#include "host-tools/core/report/report_html.hpp"
#include "tests/report/report_dom_check.hpp"
#include "tests/report/report_fixture.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fs = std::filesystem;

TEST(ReportDom, TheFixtureReportAgreesWithItself) {
  if (!fs::exists(amb::test::chromium::k_binary)) GTEST_SKIP() << "no Chromium (Debian package chromium)";
  const fs::path dir = fs::absolute(amb::test::artefact_dir()) / "report_dom";
  fs::create_directories(dir);
  const auto& d = amb::test::full_report();
  const std::string page = amb::host::report::write_event_report(d, (dir / "report.html").string());
  const nlohmann::json c = amb::test::check_report_dom(page, dir);
  // The fixture has the board's quick-look (AMBE v3 analysis) and a wear record of a fit.
  amb::test::expect_consistent_report(c, {"board quick-look", "fitted drop model (wear record)"});
  // The fit's rubbing times are named by their window, apart from the whole-window ones.
  bool fit_window = false, post_trigger = false;
  for (const auto& [name, values] : c["figures"].items()) {
    fit_window = fit_window || name == "backward rub A, fitted drop model (fit window)";
    post_trigger = post_trigger || name == "backward rub A, measured orbit (post-trigger window)";
  }
  EXPECT_TRUE(fit_window && post_trigger) << c["figures"].dump(1);
  EXPECT_NE(c["cause_chain"].get<std::string>().find("Phase A trigger"), std::string::npos) << c["cause_chain"];
}

}  // namespace
