// bearing-check's HTML page (host-tools/core/report/bearing_page.hpp): one plot per analysis band
// and its low-end zoom, the verdict, every family with its decision, and the detected family's
// lines ticked in the plot of its band.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/report/bearing_page.hpp"
#include "model/bearing/catalogue.hpp"
#include "tests/support/test_paths.hpp"

namespace hb = amb::host::bearing;
namespace hr = amb::host::report;
namespace mb = amb::model::bearing;

TEST(BearingPage, PlotsEveryBandAndTicksTheNamedFamily) {
  const std::string path = std::string(amb::test::shared_dir()) + "/data/measured/cwru/1797_IR_7_DE12.mat";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "measured data not found: " << path;
  const auto x = amb::host::read_mat_vector(path, "DE_time");
  hb::BearingCheckOptions o;
  o.keep_spectra = true;
  const auto r = hb::check_bearing(x, 12000.0, 1797.0 / 60.0, *mb::find_bearing("6205"), o);
  ASSERT_EQ(r.verdict, "inner_race");
  ASSERT_EQ(r.band_spectra.size(), r.bands.size());
  const hr::BearingPageInfo info{"1797_IR_7_DE12.mat", "DE_time", "SKF 6205", 12000.0, 1797.0};
  const std::string html = hr::render_bearing_page(r, info);
  const auto ids = hr::bearing_plot_ids(r);
  ASSERT_EQ(ids.size(), 2 * r.bands.size());
  for (const auto& id : ids) EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << id;
  EXPECT_NE(html.find("inner_race"), std::string::npos);
  for (const auto& f : r.families) {
    EXPECT_NE(html.find(">" + f.name + "<"), std::string::npos) << f.name;
    // The decision text (escaped like the page does: "<=" is "&lt;=").
    std::string reason = f.reason;
    for (size_t p = reason.find('<'); p != std::string::npos; p = reason.find('<', p)) reason.replace(p, 1, "&lt;");
    for (size_t p = reason.find('>'); p != std::string::npos; p = reason.find('>', p)) reason.replace(p, 1, "&gt;");
    EXPECT_NE(html.find(reason), std::string::npos) << f.name;
  }
  EXPECT_NE(html.find("bpfi (detected)"), std::string::npos);  // the named family's ticks are in the legend
  EXPECT_EQ(html.find("not available"), std::string::npos);

  // Without the spectra kept: no plots, and each band says so.
  const auto r0 = hb::check_bearing(x, 12000.0, 1797.0 / 60.0, *mb::find_bearing("6205"));
  EXPECT_TRUE(r0.band_spectra.empty());
  EXPECT_TRUE(hr::bearing_plot_ids(r0).empty());
  const std::string html0 = hr::render_bearing_page(r0, info);
  EXPECT_EQ(html0.find("<svg"), std::string::npos);
  EXPECT_NE(html0.find("spectrum not available"), std::string::npos);
}
