// The report rendered by a real browser: headless Chromium loads the self-contained page,
// its DOM must hold every expected <svg> plot, the console must stay free of errors, and a
// screenshot is kept as a test artefact (${build}/artefacts/report.png).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "host-tools/core/report/report_html.hpp"
#include "tests/report/report_fixture.hpp"
#include "tests/support/test_paths.hpp"


namespace {
namespace fs = std::filesystem;
const char* const k_chromium = "/usr/bin/chromium";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Run Chromium headless on `url` with `args`; stdout to `out`, stderr to `log`. Returns the exit status.
int chromium(const fs::path& profile, const std::string& args, const std::string& url, const fs::path& out, const fs::path& log) {
  const std::string cmd = std::string("timeout 120 ") + k_chromium +
                          " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                          " --disable-background-networking --disable-component-update --disable-sync"
                          " --disable-dev-shm-usage --enable-logging=stderr --v=0 --user-data-dir='" +
                          profile.string() + "' " + args + " '" + url + "' > '" + out.string() + "' 2> '" + log.string() + "'";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/// Lines of a Chromium log that report page errors.
std::string page_errors(const std::string& log) {
  std::string bad;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("Uncaught") != std::string::npos || line.find("ERROR:CONSOLE") != std::string::npos ||
        (line.find(":CONSOLE(") != std::string::npos && line.find("rror") != std::string::npos))
      bad += line + "\n";
  return bad;
}

/// Width and height from a PNG's IHDR chunk (0, 0 if it is not a PNG).
std::pair<uint32_t, uint32_t> png_size(const std::string& png) {
  if (png.size() < 24 || png.compare(1, 3, "PNG") != 0 || png.compare(12, 4, "IHDR") != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    return (static_cast<uint32_t>(static_cast<uint8_t>(png[at])) << 24) | (static_cast<uint32_t>(static_cast<uint8_t>(png[at + 1])) << 16) |
           (static_cast<uint32_t>(static_cast<uint8_t>(png[at + 2])) << 8) | static_cast<uint32_t>(static_cast<uint8_t>(png[at + 3]));
  };
  return {be32(16), be32(20)};
}

TEST(ReportChromium, RendersEveryPlotWithoutPageErrors) {
  if (!fs::exists(k_chromium))
    GTEST_SKIP() << k_chromium << " is missing: install the Debian packages chromium and chromium-driver to run this test";
  const fs::path dir = fs::absolute(amb::test::artefact_dir());
  fs::create_directories(dir);
  const auto& d = amb::test::full_report();
  const std::string page = amb::host::report::write_event_report(d, (dir / "report.html").string());
  const std::string url = "file://" + page;
  const fs::path profile = fs::temp_directory_path() / ("amb-report-chromium-" + std::to_string(::getpid()));
  fs::remove_all(profile);
  fs::create_directories(profile);

  // 1. The DOM as Chromium built it: every plot present.
  const fs::path dom = dir / "report.dom.html", log1 = dir / "chromium-dump-dom.log";
  ASSERT_EQ(chromium(profile, "--dump-dom", url, dom, log1), 0) << slurp(log1);
  const std::string html = slurp(dom);
  ASSERT_NE(html.find("<body"), std::string::npos) << "no DOM dumped:\n" << slurp(log1);
  const auto ids = amb::host::report::plot_ids(d);
  EXPECT_GE(ids.size(), 11u);
  for (const auto& id : ids) EXPECT_NE(html.find("<svg id=\"" + id + "\""), std::string::npos) << "plot missing in the DOM: " << id;
  for (const auto& id : amb::host::report::unavailable_ids(d))
    EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << "box missing in the DOM: " << id;
  EXPECT_EQ(page_errors(slurp(log1)), "");

  // 2. A screenshot: exists, has the window's size and is not blank.
  const fs::path png = dir / "report.png", log2 = dir / "chromium-screenshot.log";
  fs::remove(png);
  ASSERT_EQ(chromium(profile, "--hide-scrollbars --window-size=1280,4000 --screenshot='" + png.string() + "'", url,
                     dir / "chromium-screenshot.out", log2),
            0)
      << slurp(log2);
  ASSERT_TRUE(fs::exists(png)) << slurp(log2);
  const std::string bytes = slurp(png);
  const auto [w, h] = png_size(bytes);
  EXPECT_EQ(w, 1280u);
  EXPECT_EQ(h, 4000u);
  EXPECT_GT(bytes.size(), 60'000u) << "the screenshot is suspiciously small (blank page?)";
  EXPECT_EQ(page_errors(slurp(log2)), "");
  std::printf("[report] page %s (%zu plots), screenshot %s (%zu bytes)\n", page.c_str(), ids.size(), png.string().c_str(),
              bytes.size());
  fs::remove_all(profile);
}

}  // namespace
