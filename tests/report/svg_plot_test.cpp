// The SVG plotting helper: ticks, escaping, plot structure, decimation.
#include <gtest/gtest.h>

#include <cmath>

#include "host-tools/core/report/svg_plot.hpp"

namespace {
using namespace amb::host::report;

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

TEST(SvgPlot, NiceTicksCoverTheRangeWithRoundSteps) {
  const auto t = nice_ticks(0.0, 1.0, 5);
  ASSERT_EQ(t.size(), 6u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_NEAR(t.back(), 1.0, 1e-12);
  const auto u = nice_ticks(-3.7e-5, 2.2e-5, 6);
  ASSERT_GE(u.size(), 3u);
  EXPECT_GE(u.front(), -3.7e-5);
  EXPECT_LE(u.back(), 2.2e-5 + 1e-12);
  EXPECT_TRUE(nice_ticks(1.0, 1.0).empty());
  EXPECT_EQ(format_tick(0.25, 0.05), "0.25");
  EXPECT_EQ(format_tick(200.0, 50.0), "200");
}

TEST(SvgPlot, EscapesText) { EXPECT_EQ(escape_xml("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;"); }

TEST(SvgPlot, LinePlotHasIdAxesLegendIntervalsAndCircles) {
  LinePlot p;
  p.id = "test-plot";
  p.title = "T <1>";
  p.x_label = "time (s)";
  p.y_label = "y (m)";
  Series s{"sine", {}, {}, ""};
  for (int i = 0; i < 100; ++i) {
    s.x.push_back(i * 0.01);
    s.y.push_back(std::sin(i * 0.1));
  }
  p.series.push_back(s);
  p.intervals.push_back({0.2, 0.4, "swinging", "#2ca02c"});
  p.circles.push_back({0.0, 0.0, 0.5, "clearance"});
  const std::string svg = render_line_plot(p);
  EXPECT_EQ(svg.rfind("<svg id=\"test-plot\"", 0), 0u);
  EXPECT_NE(svg.find("T &lt;1&gt;"), std::string::npos);
  EXPECT_NE(svg.find("time (s)"), std::string::npos);
  EXPECT_NE(svg.find("class=\"legend\""), std::string::npos);
  EXPECT_NE(svg.find(">sine<"), std::string::npos);
  EXPECT_NE(svg.find(">swinging<"), std::string::npos);
  EXPECT_EQ(count(svg, "class=\"interval\""), 1u);
  EXPECT_EQ(count(svg, "<ellipse"), 1u);
  EXPECT_EQ(count(svg, "<polyline"), 1u);
  EXPECT_EQ(svg.find("<script"), std::string::npos);
}

TEST(SvgPlot, LongSeriesAreDecimatedButKeepTheirPeaks) {
  LinePlot p;
  p.id = "long";
  Series s;
  for (int i = 0; i < 200000; ++i) {
    s.x.push_back(i * 1e-4);
    s.y.push_back(i == 123457 ? 10.0 : std::sin(i * 1e-3));
  }
  p.series.push_back(s);
  const std::string svg = render_line_plot(p);
  EXPECT_LT(svg.size(), 200000u);
  // The spike's top is drawn: some point sits at the top of the y range (10 plus head room).
  const std::string poly = svg.substr(svg.find("points=\""));
  EXPECT_LT(count(poly, ","), 4000u);
  LinePlot q = p;
  q.y_range = std::array<double, 2>{-1.0, 10.0};
  const std::string svg2 = render_line_plot(q);
  // y = 10 maps to the plot top (y px = 30).
  EXPECT_NE(svg2.find(",30.00 "), std::string::npos);
}

TEST(SvgPlot, PolarPlotHasOnePolygonPerSeries) {
  PolarPlot p;
  p.id = "polar";
  p.title = "Load";
  PolarSeries a{"event", {}, {}, ""};
  for (int k = 0; k < 360; ++k) {
    a.angle_deg.push_back(k + 0.5);
    a.r.push_back(k > 150 && k < 210 ? 100.0 : 0.0);
  }
  p.series.push_back(a);
  p.series.push_back({"cumulative", a.angle_deg, a.r, ""});
  const std::string svg = render_polar_plot(p);
  EXPECT_EQ(svg.rfind("<svg id=\"polar\"", 0), 0u);
  EXPECT_EQ(count(svg, "<polygon"), 2u);
  EXPECT_NE(svg.find("180\u00b0"), std::string::npos);
}

}  // namespace
