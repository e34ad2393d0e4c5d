// The fleet page rendered by a real browser (as tests/report does for the event report):
// headless Chromium loads the self-contained page built from a store of 100 events; the DOM
// it builds holds the nearest-budget table, the trend plot with one curve per bearing and the
// machines table, without page errors; a screenshot is not blank.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "host-tools/core/fleet/fleet_report.hpp"
#include "tests/fleet/fleet_fixture.hpp"
#include "tests/support/headless_chromium.hpp"
#include "tests/support/read_text.hpp"
#include "tests/support/test_paths.hpp"

namespace fl = amb::host::fleet;
namespace tf = amb::test::fleet;
namespace fs = std::filesystem;
namespace ch = amb::test::chromium;

using amb::test::count_of;

TEST(FleetChromium, FleetPageRendersWithoutPageErrors) {
  if (!fs::exists(ch::k_binary))
    GTEST_SKIP() << ch::k_binary << " is missing: install the Debian packages chromium and chromium-driver to run this test";
  const fs::path dir = tf::fresh_dir("chromium");
  const tf::FleetFiles files = tf::make_fleet_files(dir / "files", 200);
  fl::FleetStore store((dir / "fleet.sqlite").string());
  for (const auto& f : files.all()) store.add_file(f);
  const fs::path art = fs::absolute(amb::test::artefact_dir());
  fs::create_directories(art);
  const fs::path page = art / "fleet.html";
  fl::FleetPageData d{"fleet.sqlite", store.machines(), store.nearest_budget(), store.trend()};
  std::ofstream(page) << fl::render_fleet_page(d);
  const fs::path profile = dir / "profile";
  fs::create_directories(profile);
  const std::string url = "file://" + page.string();

  const fs::path dom = art / "fleet.dom.html", log1 = dir / "dump-dom.log";
  ASSERT_EQ(ch::run(profile, "--dump-dom", url, dom, log1), 0) << ch::slurp(log1);
  const std::string html = ch::slurp(dom);
  ASSERT_NE(html.find("<body"), std::string::npos) << ch::slurp(log1);
  EXPECT_NE(html.find("<table id=\"nearest\""), std::string::npos);
  EXPECT_NE(html.find("<table id=\"machines\""), std::string::npos);
  EXPECT_NE(html.find("<svg id=\"trend\""), std::string::npos);
  // 10 bearings in the nearest table (+ header row), 5 machines, one legend entry per curve.
  const size_t t0 = html.find("<table id=\"nearest\""), t1 = html.find("</table>", t0);
  EXPECT_EQ(count_of(html.substr(t0, t1 - t0), "<tr>"), 11u);
  for (int m = 1; m <= 5; ++m) EXPECT_NE(html.find("board-" + std::to_string(m) + " aux 2"), std::string::npos) << m;
  EXPECT_EQ(ch::page_errors(ch::slurp(log1)), "");

  const fs::path png = art / "fleet.png", log2 = dir / "screenshot.log";
  fs::remove(png);
  ASSERT_EQ(ch::run(profile, "--hide-scrollbars --window-size=1280,1600 --screenshot='" + png.string() + "'", url, dir / "shot.out", log2), 0)
      << ch::slurp(log2);
  ASSERT_TRUE(fs::exists(png)) << ch::slurp(log2);
  EXPECT_GT(fs::file_size(png), 30'000u) << "the screenshot is suspiciously small (blank page?)";
  EXPECT_EQ(ch::page_errors(ch::slurp(log2)), "");
  std::printf("[fleet] page %s, screenshot %s (%ju bytes)\n", page.c_str(), png.c_str(), static_cast<uintmax_t>(fs::file_size(png)));
  fs::remove_all(dir);
}
