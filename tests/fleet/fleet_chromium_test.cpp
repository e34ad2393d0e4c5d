// The fleet page rendered by a real browser (as tests/report does for the event report):
// headless Chromium loads the self-contained page built from a store of 100 events; the DOM
// it builds holds the nearest-budget table, the trend plot with one curve per bearing and the
// machines table, without page errors; a screenshot is not blank.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "host-tools/core/fleet/fleet_report.hpp"
#include "tests/fleet/fleet_fixture.hpp"
#include "tests/support/test_paths.hpp"

namespace fl = amb::host::fleet;
namespace tf = amb::test::fleet;
namespace fs = std::filesystem;

namespace {

const char* const k_chromium = "/usr/bin/chromium";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int chromium(const fs::path& profile, const std::string& args, const std::string& url, const fs::path& out, const fs::path& log) {
  const std::string cmd = std::string("timeout 120 ") + k_chromium +
                          " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                          " --disable-background-networking --disable-component-update --disable-sync"
                          " --disable-dev-shm-usage --enable-logging=stderr --v=0 --user-data-dir='" +
                          profile.string() + "' " + args + " '" + url + "' > '" + out.string() + "' 2> '" + log.string() + "'";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string page_errors(const std::string& log) {
  std::string bad;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("Uncaught") != std::string::npos || line.find("ERROR:CONSOLE") != std::string::npos ||
        (line.find(":CONSOLE(") != std::string::npos && line.find("rror") != std::string::npos))
      bad += line + "\n";
  return bad;
}

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(FleetChromium, FleetPageRendersWithoutPageErrors) {
  if (!fs::exists(k_chromium))
    GTEST_SKIP() << k_chromium << " is missing: install the Debian packages chromium and chromium-driver to run this test";
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
  ASSERT_EQ(chromium(profile, "--dump-dom", url, dom, log1), 0) << slurp(log1);
  const std::string html = slurp(dom);
  ASSERT_NE(html.find("<body"), std::string::npos) << slurp(log1);
  EXPECT_NE(html.find("<table id=\"nearest\""), std::string::npos);
  EXPECT_NE(html.find("<table id=\"machines\""), std::string::npos);
  EXPECT_NE(html.find("<svg id=\"trend\""), std::string::npos);
  // 10 bearings in the nearest table (+ header row), 5 machines, one legend entry per curve.
  const size_t t0 = html.find("<table id=\"nearest\""), t1 = html.find("</table>", t0);
  EXPECT_EQ(count(html.substr(t0, t1 - t0), "<tr>"), 11u);
  for (int m = 1; m <= 5; ++m) EXPECT_NE(html.find("board-" + std::to_string(m) + " aux 2"), std::string::npos) << m;
  EXPECT_EQ(page_errors(slurp(log1)), "");

  const fs::path png = art / "fleet.png", log2 = dir / "screenshot.log";
  fs::remove(png);
  ASSERT_EQ(chromium(profile, "--hide-scrollbars --window-size=1280,1600 --screenshot='" + png.string() + "'", url, dir / "shot.out", log2), 0)
      << slurp(log2);
  ASSERT_TRUE(fs::exists(png)) << slurp(log2);
  EXPECT_GT(fs::file_size(png), 30'000u) << "the screenshot is suspiciously small (blank page?)";
  EXPECT_EQ(page_errors(slurp(log2)), "");
  std::printf("[fleet] page %s, screenshot %s (%ju bytes)\n", page.c_str(), png.c_str(), static_cast<uintmax_t>(fs::file_size(png)));
  fs::remove_all(dir);
}
