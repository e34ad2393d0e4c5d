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
  EXPECT_EQ(na.size(), 9u);
  for (const auto& id : na) EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << id;
  EXPECT_NE(html.find("not available:"), std::string::npos);
  EXPECT_NE(html.find("--wear FILE"), std::string::npos);
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
