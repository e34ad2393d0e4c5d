// amb-host hybrid with three CWRU operating points (issue 34): train on the 1797 and 1730 rpm
// fault records, predict the inner race at 1750 rpm / 2 hp against its measured record.
// stdout is JSON alone and the progress goes to stderr; `predict --json` gives every model's
// Pearson and MSE and the band; the --html page renders in headless Chromium without page
// errors, with both plots, the band and the baselines.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/headless_chromium.hpp"
#include "tests/support/read_text.hpp"
#include "tests/support/run_json_cli.hpp"
#include "tests/support/test_paths.hpp"

namespace fs = std::filesystem;
namespace ch = amb::test::chromium;

using amb::test::count_of;

TEST(HybridCli, ThreePointsPredictJsonHasEveryModelAndTheBandAndThePageRenders) {
  const fs::path dir = fs::temp_directory_path() / ("amb_hybrid_predict_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string d = std::string(amb::test::shared_dir()) + "/data/measured/cwru/";
  std::string recs;
  for (const char* rpm_load : {"1797,load=0", "1730,load=3"})
    for (const char* f : {"IR_7_DE12.mat,state=inner_race", "ORat6_7_DE12.mat,state=outer_race", "B_7_DE12.mat,state=ball"}) {
      const std::string rpm(rpm_load, 4);
      recs += " --record '" + d + rpm + "_" + f + ",rpm=" + rpm_load + "'";
    }
  const fs::path model = dir / "m.json", page = dir / "p.html";
  nlohmann::json j;
  std::string err;
  ASSERT_EQ(amb::test::run_json_cli(std::string(AMB_HOST_EXE) + " hybrid train --json --out '" + model.string() + "'" + recs, dir, j, err), 0)
      << err;
  EXPECT_NE(err.find("inner cross-validation"), std::string::npos) << "no progress on stderr: " << err;
  ASSERT_TRUE(j.contains("correction") && !j["correction"].is_null()) << j.dump();
  ASSERT_EQ(amb::test::run_json_cli(std::string(AMB_HOST_EXE) + " hybrid predict --json --model '" + model.string() +
                                        "' --state inner_race --rpm 1750 --load 2 --measured '" + d + "1750_IR_7_DE12.mat' --html '" +
                                        page.string() + "'",
                                    dir, j, err),
            0)
      << err;
  EXPECT_EQ(j["hybrid_kind"], "correction");
  for (const char* m : {"physics", "data_only", "nearest_transport", "interpolated_transport", "hybrid"})
    for (const char* key : {"pearson", "mse"}) {
      ASSERT_TRUE(j[key].contains(m) && !j[key][m].is_null()) << key << " " << m << ": " << j.dump().substr(0, 2000);
      EXPECT_TRUE(j[key][m]["log_spectrum"].is_number() && j[key][m]["envelope_spectrum"].is_number()) << m;
    }
  const auto& pe = j["pearson"];
  std::printf("1750 inner race: hybrid log %.3f env %.3f | interpolated transport log %.3f env %.3f\n",
              pe["hybrid"]["log_spectrum"].get<double>(), pe["hybrid"]["envelope_spectrum"].get<double>(),
              pe["interpolated_transport"]["log_spectrum"].get<double>(), pe["interpolated_transport"]["envelope_spectrum"].get<double>());
  EXPECT_EQ(j["hybrid_above_baselines"], true);
  // The band: lo <= hybrid <= hi on every bin, wider than a point somewhere.
  for (const char* sp : {"log_spectrum", "envelope_spectrum"}) {
    const auto& b = j["band"][sp];
    const auto f = b["f_hz"].get<std::vector<double>>(), y = b["hybrid"].get<std::vector<double>>(),
               lo = b["lo"].get<std::vector<double>>(), hi = b["hi"].get<std::vector<double>>();
    ASSERT_EQ(f.size(), y.size());
    ASSERT_EQ(lo.size(), y.size());
    ASSERT_EQ(hi.size(), y.size());
    double width = 0;
    for (size_t k = 0; k < y.size(); ++k) {
      EXPECT_LE(lo[k], y[k]) << sp << " bin " << k;
      EXPECT_GE(hi[k], y[k]) << sp << " bin " << k;
      width += hi[k] - lo[k];
    }
    EXPECT_GT(width, 0.0) << sp;
    const double cover = j["band"]["measured_coverage"][sp];
    EXPECT_GT(cover, 0.5) << sp;
  }

  // The page in a real browser.
  if (!fs::exists(ch::k_binary))
    GTEST_SKIP() << ch::k_binary << " is missing: install the Debian packages chromium and chromium-driver to run the page check";
  const fs::path profile = dir / "profile", dom = dir / "p.dom.html", log1 = dir / "dump-dom.log";
  fs::create_directories(profile);
  const std::string url = "file://" + page.string();
  ASSERT_EQ(ch::run(profile, "--dump-dom", url, dom, log1), 0) << ch::slurp(log1);
  const std::string html = ch::slurp(dom);
  ASSERT_NE(html.find("<body"), std::string::npos) << ch::slurp(log1);
  EXPECT_NE(html.find("<table id=\"hybrid-scores\""), std::string::npos);
  EXPECT_NE(html.find("<svg id=\"hybrid-log-spectrum\""), std::string::npos);
  EXPECT_NE(html.find("<svg id=\"hybrid-envelope\""), std::string::npos);
  EXPECT_EQ(count_of(html, "class=\"band\""), 2u) << "one band polygon per plot";
  for (const char* legend : {"measured", "hybrid band", "interpolated transport", "nearest transport", "data only", "physics ("})
    EXPECT_EQ(count_of(html, std::string(">") + legend), 2u) << legend;
  const size_t t0 = html.find("<table id=\"hybrid-scores\""), t1 = html.find("</table>", t0);
  EXPECT_EQ(count_of(html.substr(t0, t1 - t0), "<tr"), 6u) << "header and five models";
  EXPECT_EQ(ch::page_errors(ch::slurp(log1)), "");
  const fs::path art = fs::absolute(amb::test::artefact_dir());
  fs::create_directories(art);
  const fs::path png = art / "hybrid_page.png", log2 = dir / "screenshot.log";
  fs::remove(png);
  fs::copy_file(page, art / "hybrid_page.html", fs::copy_options::overwrite_existing);
  ASSERT_EQ(ch::run(profile, "--hide-scrollbars --window-size=1100,1300 --screenshot='" + png.string() + "'", url, dir / "shot.out", log2), 0)
      << ch::slurp(log2);
  ASSERT_TRUE(fs::exists(png)) << ch::slurp(log2);
  EXPECT_GT(fs::file_size(png), 30'000u) << "the screenshot is suspiciously small (blank page?)";
  EXPECT_EQ(ch::page_errors(ch::slurp(log2)), "");
  fs::remove_all(dir);
}
