#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace amb::host::report {

namespace {
constexpr double k_pi = 3.14159265358979323846;
constexpr int k_max_path_points = 4000;

struct Frame {
  double x0, x1, y0, y1;           // data ranges
  double left, top, width, height; // plot area, px
  bool log_y;
  bool log_x = false;
  double xv(double x) const { return log_x ? std::log10(x) : x; }  // x in axis units
  double px(double x) const { return left + (xv(x) - x0) / (x1 - x0) * width; }
  double py(double y) const {
    const double v = log_y ? std::log10(y) : y;
    return top + height - (v - y0) / (y1 - y0) * height;
  }
};

void expand(double& lo, double& hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = 0.0;
    hi = 1.0;
  } else if (hi <= lo) {
    const double d = lo == 0.0 ? 1.0 : std::abs(lo) * 0.1;
    lo -= d;
    hi += d;
  }
}

/// Indices of the points to draw: min/max per pixel column for time series, stride for paths.
std::vector<size_t> decimate(const Series& s, const Frame& f) {
  const size_t n = std::min(s.x.size(), s.y.size());
  std::vector<size_t> idx;
  if (n <= static_cast<size_t>(k_max_path_points)) {
    idx.resize(n);
    for (size_t i = 0; i < n; ++i) idx[i] = i;
    return idx;
  }
  if (s.path) {
    const size_t stride = (n + k_max_path_points - 1) / k_max_path_points;
    for (size_t i = 0; i < n; i += stride) idx.push_back(i);
    if (idx.back() != n - 1) idx.push_back(n - 1);
    return idx;
  }
  const int columns = std::max(1, static_cast<int>(f.width));
  int col = -1;
  size_t lo = 0, hi = 0, first = 0;
  auto flush = [&] {
    if (col < 0) return;
    const size_t a = std::min(lo, hi), b = std::max(lo, hi);
    idx.push_back(first);
    if (a != first) idx.push_back(a);
    if (b != a && b != first) idx.push_back(b);
  };
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
    if (f.log_x && !(s.x[i] > 0.0)) continue;
    const int c = std::clamp(static_cast<int>((f.xv(s.x[i]) - f.x0) / (f.x1 - f.x0) * columns), -1, columns);
    if (c != col) {
      flush();
      col = c;
      lo = hi = first = i;
    } else {
      if (s.y[i] < s.y[lo]) lo = i;
      if (s.y[i] > s.y[hi]) hi = i;
    }
  }
  flush();
  return idx;
}

std::string polyline(const Series& s, const Frame& f, const std::string& color) {
  std::string out;
  std::string pts;
  auto close = [&] {
    if (pts.empty()) return;
    out += "<polyline fill=\"none\" stroke=\"" + escape_xml(color) + "\" stroke-width=\"" + io::printf_text("%.2f", s.width_px) + "\"" +
           (s.dashed ? " stroke-dasharray=\"5 3\"" : "") + " stroke-linejoin=\"round\" points=\"" + pts + "\"/>\n";
    pts.clear();
  };
  for (size_t i : decimate(s, f)) {
    const double x = s.x[i], y = s.y[i];
    if (!std::isfinite(x) || !std::isfinite(y) || (f.log_y && y <= 0.0) || (f.log_x && x <= 0.0)) {
      close();
      continue;
    }
    pts += io::printf_text("%.2f", f.px(x)) + "," + io::printf_text("%.2f", f.py(y)) + " ";
  }
  close();
  return out;
}

std::string text(double x, double y, const std::string& t, const char* anchor, int size = 12, const char* extra = "") {
  return "<text x=\"" + io::printf_text("%.2f", x) + "\" y=\"" + io::printf_text("%.2f", y) + "\" font-size=\"" + std::to_string(size) + "\" text-anchor=\"" +
         anchor + "\"" + extra + ">" + escape_xml(t) + "</text>\n";
}
}  // namespace

const char* palette(size_t i) {
  static const char* const k[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"};
  return k[i % (sizeof k / sizeof k[0])];
}

std::string escape_xml(std::string_view s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&#39;"; break;
      default: o += c;
    }
  }
  return o;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> t;
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi <= lo || target < 1) return t;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  const double first = std::ceil(lo / step - 1e-9) * step;
  for (double v = first; v <= hi + step * 1e-9; v += step) t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  return t;
}

std::string format_tick(double v, double step) {
  char b[32];
  const double a = std::abs(step);
  if (v != 0.0 && (std::abs(v) >= 1e5 || std::abs(v) < 1e-3)) {
    std::snprintf(b, sizeof b, "%.3g", v);
  } else {
    const int decimals = a >= 1.0 ? 0 : std::min(6, static_cast<int>(std::ceil(-std::log10(a) - 1e-9)));
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
  }
  return b;
}

std::string render_line_plot(const LinePlot& p) {
  // Data ranges.
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const Series& s : p.series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (p.log_y && s.y[i] <= 0.0) || (p.log_x && s.x[i] <= 0.0)) continue;
      x0 = std::min(x0, p.log_x ? std::log10(s.x[i]) : s.x[i]);
      x1 = std::max(x1, p.log_x ? std::log10(s.x[i]) : s.x[i]);
      const double y = p.log_y ? std::log10(s.y[i]) : s.y[i];
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
  for (const Band& b : p.bands)
    for (size_t i = 0; i < std::min({b.x.size(), b.lo.size(), b.hi.size()}); ++i) {
      if (!std::isfinite(b.x[i]) || !std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) continue;
      if ((p.log_y && (b.lo[i] <= 0.0 || b.hi[i] <= 0.0)) || (p.log_x && b.x[i] <= 0.0)) continue;
      x0 = std::min(x0, p.log_x ? std::log10(b.x[i]) : b.x[i]);
      x1 = std::max(x1, p.log_x ? std::log10(b.x[i]) : b.x[i]);
      y0 = std::min(y0, p.log_y ? std::log10(b.lo[i]) : b.lo[i]);
      y1 = std::max(y1, p.log_y ? std::log10(b.hi[i]) : b.hi[i]);
    }
  for (const Circle& c : p.circles) {
    x0 = std::min(x0, c.cx - c.r);
    x1 = std::max(x1, c.cx + c.r);
    y0 = std::min(y0, c.cy - c.r);
    y1 = std::max(y1, c.cy + c.r);
  }
  for (const Interval& iv : p.intervals) {
    if (!std::isfinite(x0)) x0 = iv.x0;
    if (!std::isfinite(x1)) x1 = iv.x1;
  }
  if (p.x_range) {
    x0 = p.log_x ? std::log10((*p.x_range)[0]) : (*p.x_range)[0];
    x1 = p.log_x ? std::log10((*p.x_range)[1]) : (*p.x_range)[1];
  }
  if (p.y_range) {
    y0 = p.log_y ? std::log10((*p.y_range)[0]) : (*p.y_range)[0];
    y1 = p.log_y ? std::log10((*p.y_range)[1]) : (*p.y_range)[1];
  }
  expand(x0, x1);
  expand(y0, y1);
  if (!p.y_range && !p.log_y) {  // a little head room
    const double pad = 0.04 * (y1 - y0);
    y0 -= pad;
    y1 += pad;
  }

  // Legend entries decide the right margin.
  struct LegendLine {
    std::string label, colour;
    bool dashed = false;  ///< drawn as the series is (a dashed series gets a dashed legend line)
  };
  std::vector<LegendLine> legend;
  std::vector<std::string> colours;
  for (size_t i = 0; i < p.series.size(); ++i) {
    colours.push_back(p.series[i].color.empty() ? palette(i) : p.series[i].color);
    if (!p.series[i].label.empty()) legend.push_back({p.series[i].label, colours.back(), p.series[i].dashed});
  }
  std::map<std::string, std::string> band_legend;
  for (const Interval& iv : p.intervals)
    if (!iv.label.empty()) band_legend.emplace(iv.label, iv.color);
  for (const Circle& c : p.circles)
    if (!c.label.empty()) legend.push_back({c.label, c.color, c.dashed});
  for (const Band& b : p.bands)
    if (!b.label.empty()) band_legend.emplace(b.label, b.color);

  Frame f{x0, x1, y0, y1, 70.0, 30.0, static_cast<double>(p.width_px) - 70.0 - 16.0,
          static_cast<double>(p.height_px) - 30.0 - 48.0, p.log_y, p.log_x};
  const bool has_legend = !legend.empty() || !band_legend.empty();
  // The legend's margin fits its longest label (about 6.3 px a character at 11 px sans-serif;
  // a fixed 150 px clipped longer labels such as "model + sensor_runout").
  size_t longest = 0;
  for (const LegendLine& l : legend) longest = std::max(longest, l.label.size());
  for (const auto& [label, colour] : band_legend) longest = std::max(longest, label.size());
  const double legend_w = std::max(150.0, 14.0 + 24.0 + 6.3 * static_cast<double>(longest) + 6.0);
  if (has_legend) f.width -= legend_w;
  if (p.equal_aspect) {
    // Same m per px on both axes: widen the range of the axis that has room to spare.
    const double sx = (f.x1 - f.x0) / f.width, sy = (f.y1 - f.y0) / f.height;
    if (sx > sy) {
      const double c = 0.5 * (f.y0 + f.y1), h = 0.5 * sx * f.height;
      f.y0 = c - h;
      f.y1 = c + h;
    } else {
      const double c = 0.5 * (f.x0 + f.x1), h = 0.5 * sy * f.width;
      f.x0 = c - h;
      f.x1 = c + h;
    }
  }

  std::string s;
  s += "<svg id=\"" + escape_xml(p.id) + "\" class=\"plot\"" + (p.log_y ? " data-log-y=\"1\"" : "") +
       " xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(p.width_px) + "\" height=\"" +
       std::to_string(p.height_px) + "\" viewBox=\"0 0 " +
       std::to_string(p.width_px) + " " + std::to_string(p.height_px) + "\" font-family=\"sans-serif\">\n";
  s += "<title>" + escape_xml(p.title) + "</title>\n";
  s += "<rect x=\"0\" y=\"0\" width=\"" + std::to_string(p.width_px) + "\" height=\"" + std::to_string(p.height_px) +
       "\" fill=\"white\"/>\n";
  s += text(f.left + f.width / 2, 18, p.title, "middle", 14, " font-weight=\"bold\"");
  // Clip the data to the plot area.
  s += "<clipPath id=\"" + escape_xml(p.id) + "-clip\"><rect x=\"" + io::printf_text("%.2f", f.left) + "\" y=\"" + io::printf_text("%.2f", f.top) + "\" width=\"" +
       io::printf_text("%.2f", f.width) + "\" height=\"" + io::printf_text("%.2f", f.height) + "\"/></clipPath>\n";

  // Ticks and grid.
  std::vector<double> xt;  // tick values in data units
  if (p.log_x) {
    // 1, 2, 5 x 10^k inside the range (decades only when that gives enough).
    for (double e = std::floor(f.x0); e <= std::ceil(f.x1); ++e)
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * std::pow(10.0, e);
        if (std::log10(v) >= f.x0 - 1e-9 && std::log10(v) <= f.x1 + 1e-9) xt.push_back(v);
      }
    if (xt.size() > 9) {
      std::vector<double> decades;
      for (double v : xt)
        if (std::abs(std::log10(v) - std::round(std::log10(v))) < 1e-9) decades.push_back(v);
      if (decades.size() >= 2) xt = decades;
    }
  } else {
    xt = nice_ticks(f.x0, f.x1, std::max(3, static_cast<int>(f.width / 90)));
  }
  const double xstep = p.log_x ? 0.0 : (xt.size() > 1 ? xt[1] - xt[0] : 1.0);
  for (double v : xt) {
    const double x = f.px(v);
    s += "<line x1=\"" + io::printf_text("%.2f", x) + "\" y1=\"" + io::printf_text("%.2f", f.top) + "\" x2=\"" + io::printf_text("%.2f", x) + "\" y2=\"" + io::printf_text("%.2f", f.top + f.height) +
         "\" stroke=\"#e4e4e4\"/>\n";
    s += text(x, f.top + f.height + 15, p.log_x ? io::printf_text("%g", v) : format_tick(v, xstep), "middle", 11, " class=\"xtick\"");
  }
  std::vector<double> yt;
  if (p.log_y) {
    for (double e = std::ceil(f.y0 - 1e-9); e <= f.y1 + 1e-9; e += std::max(1.0, std::ceil((f.y1 - f.y0) / 6))) yt.push_back(e);
    // Less than about a decade shown: 2 and 5 times the decades too, and if that is still too
    // few, round values of the linear range (a log axis without tick values reads as nothing).
    if (yt.size() < 3) {
      yt.clear();
      for (double e = std::floor(f.y0) - 1; e <= std::ceil(f.y1) + 1; ++e)
        for (double m : {1.0, 2.0, 5.0}) {
          const double v = e + std::log10(m);
          if (v >= f.y0 - 1e-9 && v <= f.y1 + 1e-9) yt.push_back(v);
        }
    }
    if (yt.size() < 3) {
      yt.clear();
      for (double v : nice_ticks(std::pow(10.0, f.y0), std::pow(10.0, f.y1), 4))
        if (v > 0.0) yt.push_back(std::log10(v));
    }
  } else {
    yt = nice_ticks(f.y0, f.y1, std::max(3, static_cast<int>(f.height / 50)));
  }
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (double v : yt) {
    const double y = f.top + f.height - (v - f.y0) / (f.y1 - f.y0) * f.height;
    s += "<line x1=\"" + io::printf_text("%.2f", f.left) + "\" y1=\"" + io::printf_text("%.2f", y) + "\" x2=\"" + io::printf_text("%.2f", f.left + f.width) + "\" y2=\"" + io::printf_text("%.2f", y) +
         "\" stroke=\"#e4e4e4\"/>\n";
    std::string label;
    if (p.log_y) {
      char b[32];
      if (std::fabs(v - std::round(v)) < 1e-9)
        std::snprintf(b, sizeof b, "1e%d", static_cast<int>(std::lround(v)));
      else
        std::snprintf(b, sizeof b, "%.3g", std::pow(10.0, v));
      label = b;
    } else {
      label = format_tick(v, ystep);
    }
    s += text(f.left - 6, y + 4, label, "end", 11, " class=\"ytick\"");
  }

  s += "<g clip-path=\"url(#" + escape_xml(p.id) + "-clip)\">\n";
  for (const Interval& iv : p.intervals) {
    const double a = f.px(std::max(iv.x0, f.x0)), b = f.px(std::min(iv.x1, f.x1));
    if (b <= a) continue;
    s += "<rect class=\"interval\" x=\"" + io::printf_text("%.2f", a) + "\" y=\"" + io::printf_text("%.2f", f.top) + "\" width=\"" + io::printf_text("%.2f", b - a) + "\" height=\"" +
         io::printf_text("%.2f", f.height) + "\" fill=\"" + escape_xml(iv.color) + "\" fill-opacity=\"0.25\"/>\n";
  }
  for (const Circle& c : p.circles) {
    const double rx = c.r / (f.x1 - f.x0) * f.width, ry = c.r / (f.y1 - f.y0) * f.height;
    s += "<ellipse cx=\"" + io::printf_text("%.2f", f.px(c.cx)) + "\" cy=\"" + io::printf_text("%.2f", f.py(c.cy)) + "\" rx=\"" + io::printf_text("%.2f", rx) + "\" ry=\"" + io::printf_text("%.2f", ry) +
         "\" fill=\"none\" stroke=\"" + escape_xml(c.color) + "\" stroke-width=\"1.5\"" +
         (c.dashed ? " stroke-dasharray=\"6 4\"" : "") + "/>\n";
  }
  for (const Band& b : p.bands) {
    std::string upper, lower;
    const size_t n = std::min({b.x.size(), b.lo.size(), b.hi.size()});
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(b.x[i]) || !std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) continue;
      if ((p.log_y && (b.lo[i] <= 0.0 || b.hi[i] <= 0.0)) || (p.log_x && b.x[i] <= 0.0)) continue;
      upper += io::printf_text("%.2f", f.px(b.x[i])) + "," + io::printf_text("%.2f", f.py(b.hi[i])) + " ";
    }
    for (size_t i = n; i-- > 0;) {
      if (!std::isfinite(b.x[i]) || !std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) continue;
      if ((p.log_y && (b.lo[i] <= 0.0 || b.hi[i] <= 0.0)) || (p.log_x && b.x[i] <= 0.0)) continue;
      lower += io::printf_text("%.2f", f.px(b.x[i])) + "," + io::printf_text("%.2f", f.py(b.lo[i])) + " ";
    }
    if (!upper.empty())
      s += "<polygon class=\"band\" points=\"" + upper + lower + "\" fill=\"" + escape_xml(b.color) +
           "\" fill-opacity=\"0.3\" stroke=\"none\"/>\n";
  }
  for (size_t i = 0; i < p.series.size(); ++i) s += polyline(p.series[i], f, colours[i]);
  s += "</g>\n";

  // Axes frame and labels.
  s += "<rect x=\"" + io::printf_text("%.2f", f.left) + "\" y=\"" + io::printf_text("%.2f", f.top) + "\" width=\"" + io::printf_text("%.2f", f.width) + "\" height=\"" + io::printf_text("%.2f", f.height) +
       "\" fill=\"none\" stroke=\"#333\"/>\n";
  s += text(f.left + f.width / 2, f.top + f.height + 36, p.x_label, "middle", 12);
  const double ly = f.top + f.height / 2;
  s += "<text x=\"16\" y=\"" + io::printf_text("%.2f", ly) + "\" font-size=\"12\" text-anchor=\"middle\" transform=\"rotate(-90 16 " + io::printf_text("%.2f", ly) +
       ")\">" + escape_xml(p.y_label) + "</text>\n";

  if (has_legend) {
    double y = f.top + 8;
    const double x = f.left + f.width + 14;
    s += "<g class=\"legend\">\n";
    for (const LegendLine& l : legend) {
      s += "<line x1=\"" + io::printf_text("%.2f", x) + "\" y1=\"" + io::printf_text("%.2f", y) + "\" x2=\"" + io::printf_text("%.2f", x + 18) + "\" y2=\"" + io::printf_text("%.2f", y) + "\" stroke=\"" +
           escape_xml(l.colour) + "\" stroke-width=\"2.5\"" + (l.dashed ? " stroke-dasharray=\"5 3\"" : "") + "/>\n";
      s += text(x + 24, y + 4, l.label, "start", 11);
      y += 17;
    }
    for (const auto& [label, colour] : band_legend) {
      s += "<rect x=\"" + io::printf_text("%.2f", x) + "\" y=\"" + io::printf_text("%.2f", y - 6) + "\" width=\"18\" height=\"12\" fill=\"" + escape_xml(colour) +
           "\" fill-opacity=\"0.35\"/>\n";
      s += text(x + 24, y + 4, label, "start", 11);
      y += 17;
    }
    s += "</g>\n";
  }
  s += "</svg>\n";
  return s;
}

std::string render_polar_plot(const PolarPlot& p) {
  const int legend_w = 170;
  const int w = p.size_px + legend_w, h = p.size_px + 40;
  const double cx = p.size_px / 2.0, cy = 30.0 + p.size_px / 2.0 - 6.0, radius = p.size_px / 2.0 - 34.0;
  double rmax = 0.0;
  for (const PolarSeries& ps : p.series)
    for (double r : ps.r)
      if (std::isfinite(r)) rmax = std::max(rmax, r);
  const auto rt = nice_ticks(0.0, rmax > 0.0 ? rmax : 1.0, 4);
  const double rtop = rt.empty() ? 1.0 : std::max(rt.back(), rmax > 0.0 ? rmax : 1.0);
  const double rstep = rt.size() > 1 ? rt[1] - rt[0] : rtop;
  // Board convention: 0 deg up, positive towards +x (clockwise on the screen).
  auto pt = [&](double a_deg, double r) {
    const double a = a_deg * k_pi / 180.0, q = r / rtop * radius;
    return std::array<double, 2>{cx + q * std::sin(a), cy - q * std::cos(a)};
  };

  std::string s = "<svg id=\"" + escape_xml(p.id) + "\" class=\"plot polar\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                  std::to_string(w) + "\" height=\"" + std::to_string(h) + "\" viewBox=\"0 0 " + std::to_string(w) + " " +
                  std::to_string(h) + "\" font-family=\"sans-serif\">\n";
  s += "<title>" + escape_xml(p.title) + "</title>\n";
  s += "<rect x=\"0\" y=\"0\" width=\"" + std::to_string(w) + "\" height=\"" + std::to_string(h) + "\" fill=\"white\"/>\n";
  s += text(cx, 18, p.title, "middle", 14, " font-weight=\"bold\"");
  for (double r : rt) {
    if (r <= 0.0) continue;
    s += "<circle cx=\"" + io::printf_text("%.2f", cx) + "\" cy=\"" + io::printf_text("%.2f", cy) + "\" r=\"" + io::printf_text("%.2f", r / rtop * radius) +
         "\" fill=\"none\" stroke=\"#ddd\"/>\n";
    const auto q = pt(0.0, r);
    s += text(q[0] + 3, q[1] - 2, format_tick(r, rstep), "start", 10, " fill=\"#666\"");
  }
  for (int a = 0; a < 360; a += 30) {
    const auto q = pt(a, rtop), l = pt(a, rtop * 1.13);
    s += "<line x1=\"" + io::printf_text("%.2f", cx) + "\" y1=\"" + io::printf_text("%.2f", cy) + "\" x2=\"" + io::printf_text("%.2f", q[0]) + "\" y2=\"" + io::printf_text("%.2f", q[1]) +
         "\" stroke=\"#e4e4e4\"/>\n";
    s += text(l[0], l[1] + 4, std::to_string(a) + "\u00b0", "middle", 10);
  }
  s += "<circle cx=\"" + io::printf_text("%.2f", cx) + "\" cy=\"" + io::printf_text("%.2f", cy) + "\" r=\"" + io::printf_text("%.2f", radius) + "\" fill=\"none\" stroke=\"#333\"/>\n";
  double ly = 40.0;
  for (size_t i = 0; i < p.series.size(); ++i) {
    const PolarSeries& ps = p.series[i];
    const std::string colour = ps.color.empty() ? palette(i) : ps.color;
    std::string pts;
    for (size_t k = 0; k < std::min(ps.angle_deg.size(), ps.r.size()); ++k) {
      if (!std::isfinite(ps.r[k]) || !std::isfinite(ps.angle_deg[k])) continue;
      const auto q = pt(ps.angle_deg[k], std::max(0.0, ps.r[k]));
      pts += io::printf_text("%.2f", q[0]) + "," + io::printf_text("%.2f", q[1]) + " ";
    }
    s += "<polygon points=\"" + pts + "\" fill=\"" + escape_xml(colour) + "\" fill-opacity=\"" + (ps.fill ? "0.25" : "0") +
         "\" stroke=\"" + escape_xml(colour) + "\" stroke-width=\"1.5\"/>\n";
    if (!ps.label.empty()) {
      // The swatch is drawn as the series is: filled, or an outline.
      s += "<rect x=\"" + io::printf_text("%.2f", p.size_px + 6.0) + "\" y=\"" + io::printf_text("%.2f", ly - 8) + "\" width=\"16\" height=\"10\" fill=\"" +
           escape_xml(colour) + "\" fill-opacity=\"" + (ps.fill ? "0.25" : "0") + "\" stroke=\"" + escape_xml(colour) +
           "\" stroke-width=\"1.5\"/>\n";
      s += text(p.size_px + 28.0, ly + 1, ps.label, "start", 11);
      ly += 17;
    }
  }
  // The radius unit, wrapped to the legend's width (it used to run off the picture).
  std::vector<std::string> lines{""};
  std::string word;
  for (char c : p.r_label + " ") {
    if (c != ' ') {
      word += c;
      continue;
    }
    if (!lines.back().empty() && lines.back().size() + 1 + word.size() > 24) lines.emplace_back();
    lines.back() += (lines.back().empty() ? "" : " ") + word;
    word.clear();
  }
  for (const std::string& l : lines) {
    s += text(p.size_px + 6.0, ly + 12, l, "start", 11, " fill=\"#444\"");
    ly += 14;
  }
  s += text(p.size_px + 6.0, ly + 14, "0\u00b0 = up, 180\u00b0 = bottom", "start", 10, " fill=\"#666\"");
  s += "</svg>\n";
  return s;
}

}  // namespace amb::host::report
