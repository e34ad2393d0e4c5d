// The report page: every plot of every available section, a "not available" box for every
// missing one, self-contained (no scripts, no external resources).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "host-tools/core/report/report_builder.hpp"
#include "host-tools/core/report/report_html.hpp"
#include "tests/report/report_fixture.hpp"

namespace {
using namespace amb::host::report;

TEST(ReportHtml, EmptyReportShowsWhyEverySectionIsMissing) {
  const ReportData d = new_report_data("empty");
  const std::string html = render_event_report(d);
  EXPECT_TRUE(plot_ids(d).empty());
  const auto na = unavailable_ids(d);
  EXPECT_EQ(na.size(), 10u);  // every section but the facts
  for (const auto& id : na) EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << id;
  EXPECT_NE(html.find("not available:"), std::string::npos);
  EXPECT_NE(html.find("--wear FILE"), std::string::npos);
}

TEST(ReportHtml, DropResidualSectionShowsTheAddedElementAndTheCentres) {
  ReportData d = new_report_data("drop residual");
  amb::host::residual::DropResidualOutcome o;
  o.verdict = "aux_bearing_offset";
  o.levitated_note = "levitated part not analysed: 0.50 s of pre-trigger history < 1.00 s";
  o.effects_added.push_back({"aux_bearing_offset", {{"x0_m", 5.5e-5}, {"y0_m", -4.3e-5}}, "contact circles off", 172.5});
  o.drop_before.measured_circle[0].valid = true;
  o.drop_before.measured_circle[0].centre_m = {55.4e-6, -43.2e-6};
  o.drop_before.measured_circle[0].sigma_m = 2.3e-6;
  add_drop_residual(d, o, "drop_run.json");
  const auto na = unavailable_ids(d);
  EXPECT_EQ(std::find(na.begin(), na.end(), "drop-residual-na"), na.end());
  const std::string html = render_event_report(d);
  EXPECT_NE(html.find("<section id=\"drop-residual\">"), std::string::npos);
  EXPECT_NE(html.find("added aux_bearing_offset"), std::string::npos);
  EXPECT_NE(html.find("+55.4 / -43.2 um"), std::string::npos);
  EXPECT_NE(html.find("pre-trigger history"), std::string::npos);
}

TEST(ReportHtml, FullReportHasEveryPlotAndIsSelfContained) {
  const ReportData& d = amb::test::full_report();
  const std::string html = render_event_report(d);
  const auto ids = plot_ids(d);
  // Orbits (2), contact angle + slope (2 x 2), speed, forces, load (2), fit convergence.
  for (const char* id : {"orbit-a", "orbit-b", "contact-angle-a", "contact-slope-a", "contact-angle-b", "contact-slope-b",
                         "speed", "contact-forces", "load-a", "load-b", "fit-convergence"}) {
    EXPECT_NE(std::find(ids.begin(), ids.end(), id), ids.end()) << id;
    EXPECT_NE(html.find(std::string("<svg id=\"") + id + "\""), std::string::npos) << id;
  }
  EXPECT_TRUE(d.replay.available());
  EXPECT_TRUE(d.replay.data->reproduced);
  EXPECT_FALSE(d.residual.available());
  EXPECT_NE(html.find("id=\"residual-na\""), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // only the SVG namespace
  EXPECT_EQ(html.find("https://"), std::string::npos);
}

TEST(ReportHtml, WriteEventReportWritesThePage) {
  const auto dir = std::filesystem::temp_directory_path() / "amb_report_test";
  const std::string path = write_event_report(new_report_data("x"), (dir / "sub" / "r.html").string());
  EXPECT_TRUE(std::filesystem::path(path).is_absolute());
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("<!DOCTYPE html>"), std::string::npos);
  EXPECT_THROW(write_event_report(new_report_data("x"), "/proc/no/such/dir/r.html"), std::runtime_error);
}

}  // namespace

// Speed section (issue 32): the rig's tachometer beside the board's estimate, and the spans where
// the board had no valid speed shaded as "not tracked" (one band per run of lost samples).
TEST(ReportHtml, SpeedSectionShowsTheTachometerAndTheNotTrackedSpans) {
  ReportData d = new_report_data("speed");
  amb::host::report::SpeedTrace sp;
  for (int i = 0; i < 100; ++i) {
    const double t = 0.01 * i;
    const bool lost = (i >= 20 && i < 40) || i >= 70;
    sp.t_s.push_back(t);
    sp.plant_speed_hz.push_back(45.0 - 10.0 * t);
    sp.speed_hz.push_back(lost ? NAN : 45.0 - 10.0 * t);
    sp.speed_command_hz.push_back(i < 50 ? 45.0 : 0.0);
    sp.not_tracked.push_back(lost ? 1 : 0);
  }
  d.speed.set(std::move(sp), "test");
  const std::string html = render_event_report(d);
  EXPECT_NE(html.find("tachometer"), std::string::npos);
  EXPECT_NE(html.find("not tracked"), std::string::npos);  // legend entry
  // One shaded band per run of lost samples: two runs (samples 20-39 and 70-99).
  const std::string band = "fill=\"#bbbbbb\" fill-opacity=\"0.25\"";
  size_t bands = 0;
  for (size_t p = html.find(band); p != std::string::npos; p = html.find(band, p + 1)) ++bands;
  EXPECT_EQ(bands, 2u);
  const auto ids = plot_ids(d);
  EXPECT_NE(std::find(ids.begin(), ids.end(), "speed"), ids.end());
}
