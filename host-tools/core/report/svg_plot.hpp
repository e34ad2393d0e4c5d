#pragma once
// A small SVG plotting helper for self-contained HTML reports (no JavaScript): line plots
// with axes, "nice" ticks, labels, a legend, shaded x intervals and circles (e.g. a
// clearance), and a polar plot. Output is an <svg> element with the plot's id, sized in CSS
// pixels, that a browser renders inline.
//
// Long series are decimated for drawing (min/max per pixel column for time series, so peaks
// survive; an even stride for x-y paths); the data passed in is not changed.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace amb::host::report {

/// One curve of a line plot.
struct Series {
  std::string label;           ///< legend text (empty: not in the legend)
  std::vector<double> x, y;    ///< same length; non-finite points break the line
  std::string color;           ///< CSS colour; empty: next of the palette
  double width_px = 1.4;       ///< stroke width, px
  bool dashed = false;
  bool path = false;           ///< x-y path (orbit): decimate by stride, not per x column
};

/// A shaded band over an x range (e.g. a rubbing state).
struct Interval {
  double x0 = 0.0, x1 = 0.0;   ///< x range (data units)
  std::string label;           ///< legend text (one legend entry per distinct label)
  std::string color;           ///< CSS colour of the band (drawn with opacity)
};

/// A circle in data units (e.g. the clearance circle of an orbit plot).
struct Circle {
  double cx = 0.0, cy = 0.0, r = 0.0;
  std::string label;
  std::string color = "#444";
  bool dashed = true;
};

/// A shaded band between two curves over x (e.g. a prediction's uncertainty band); drawn under
/// the series as a filled polygon (class "band").
struct Band {
  std::string label;               ///< legend text (empty: not in the legend)
  std::vector<double> x, lo, hi;   ///< same length; points with a non-finite value are skipped
  std::string color = "#888";      ///< CSS colour (drawn with opacity)
};

struct LinePlot {
  std::string id;              ///< id of the <svg> element (unique in the page)
  std::string title;
  std::string x_label, y_label;///< with units, e.g. "time from trigger (s)"
  std::vector<Series> series;
  std::vector<Interval> intervals;
  std::vector<Circle> circles;
  std::vector<Band> bands;
  bool equal_aspect = false;   ///< same scale on x and y (orbits)
  bool log_y = false;          ///< logarithmic y axis (values <= 0 are dropped)
  bool log_x = false;          ///< logarithmic x axis (values <= 0 are dropped; ticks at 1, 2, 5 x 10^k; not with intervals or circles)
  std::optional<std::array<double, 2>> x_range, y_range;  ///< fixed ranges (else from the data)
  int width_px = 640, height_px = 340;
};

/// One closed curve of a polar plot.
struct PolarSeries {
  std::string label;
  std::vector<double> angle_deg;  ///< polar angle, deg from the upward vertical, positive towards +x (clockwise on screen)
  std::vector<double> r;          ///< radius (data units, >= 0)
  std::string color;
  bool fill = true;               ///< fill the enclosed area (translucent)
};

struct PolarPlot {
  std::string id;
  std::string title;
  std::string r_label;            ///< unit of the radius, e.g. "load sum (N)"
  std::vector<PolarSeries> series;
  int size_px = 360;              ///< width and height of the plot area
};

/// The <svg> element of a line plot / polar plot.
std::string render_line_plot(const LinePlot& p);
std::string render_polar_plot(const PolarPlot& p);

/// About `target` round tick values covering [lo, hi] (1, 2, 5 x 10^k steps).
std::vector<double> nice_ticks(double lo, double hi, int target = 6);
/// Tick text: short, without trailing zeros (e.g. "0.25", "-1e-05", "200").
std::string format_tick(double v, double step);
/// Escape &, <, >, " and ' for XML/HTML text and attributes.
std::string escape_xml(std::string_view s);
/// The i-th colour of the default palette.
const char* palette(size_t i);

}  // namespace amb::host::report
