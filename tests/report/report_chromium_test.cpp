// The report rendered by a real browser: headless Chromium loads the self-contained page,
// its DOM must hold every expected <svg> plot, the console must stay free of errors, and a
// screenshot is kept as a test artefact (${build}/artefacts/report.png).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "host-tools/core/report/report_html.hpp"
#include "tests/report/report_fixture.hpp"
#include "tests/support/headless_chromium.hpp"
#include "tests/support/test_paths.hpp"

namespace fs = std::filesystem;
namespace ch = amb::test::chromium;

TEST(ReportChromium, RendersEveryPlotWithoutPageErrors) {
  if (!fs::exists(ch::k_binary))
    GTEST_SKIP() << ch::k_binary << " is missing: install the Debian packages chromium and chromium-driver to run this test";
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
  ASSERT_EQ(ch::run(profile, "--dump-dom", url, dom, log1), 0) << ch::slurp(log1);
  const std::string html = ch::slurp(dom);
  ASSERT_NE(html.find("<body"), std::string::npos) << "no DOM dumped:\n" << ch::slurp(log1);
  const auto ids = amb::host::report::plot_ids(d);
  EXPECT_GE(ids.size(), 11u);
  for (const auto& id : ids) EXPECT_NE(html.find("<svg id=\"" + id + "\""), std::string::npos) << "plot missing in the DOM: " << id;
  for (const auto& id : amb::host::report::unavailable_ids(d))
    EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << "box missing in the DOM: " << id;
  EXPECT_EQ(ch::page_errors(ch::slurp(log1)), "");

  // 2. A screenshot: exists, has the window's size and is not blank.
  const fs::path png = dir / "report.png", log2 = dir / "chromium-screenshot.log";
  fs::remove(png);
  ASSERT_EQ(ch::run(profile, "--hide-scrollbars --window-size=1280,4000 --screenshot='" + png.string() + "'", url,
                     dir / "chromium-screenshot.out", log2),
            0)
      << ch::slurp(log2);
  ASSERT_TRUE(fs::exists(png)) << ch::slurp(log2);
  const std::string bytes = ch::slurp(png);
  const auto [w, h] = ch::png_size(bytes);
  EXPECT_EQ(w, 1280u);
  EXPECT_EQ(h, 4000u);
  EXPECT_GT(bytes.size(), 60'000u) << "the screenshot is suspiciously small (blank page?)";
  EXPECT_EQ(ch::page_errors(ch::slurp(log2)), "");
  std::printf("[report] page %s (%zu plots), screenshot %s (%zu bytes)\n", page.c_str(), ids.size(), png.string().c_str(),
              bytes.size());
  fs::remove_all(profile);
}
