#include "host-tools/core/envelope/envelope_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::envelope {
namespace {

namespace rp = amb::host::report;

/// Colour of t in [0, 1] on a blue -> yellow -> red scale.
std::string ramp(double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  const double stops[3][3] = {{49, 54, 149}, {254, 224, 144}, {165, 0, 38}};
  const int i = t < 0.5 ? 0 : 1;
  const double u = t < 0.5 ? t * 2.0 : (t - 0.5) * 2.0;
  char b[16];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", static_cast<int>(stops[i][0] + u * (stops[i + 1][0] - stops[i][0])),
                static_cast<int>(stops[i][1] + u * (stops[i + 1][1] - stops[i][1])),
                static_cast<int>(stops[i][2] + u * (stops[i + 1][2] - stops[i][2])));
  return b;
}

const char* whirl_colour(const std::string& w) {
  if (w == "backward") return "#c0392b";
  if (w == "forward") return "#e67e22";
  if (w == "bouncing") return "#2980b9";
  return "#95a5a6";
}

std::string axis_label(const std::string& p) {
  if (p == "speed_hz") return "speed before the drop (Hz)";
  if (p == "friction") return "friction coefficient (1)";
  if (p == "unbalance_factor") return "unbalance (factor on the board's)";
  if (p == "clearance_m") return "clearance (m)";
  if (p == "offset_x_m") return "centre offset x (m)";
  if (p == "offset_y_m") return "centre offset y (m)";
  if (p == "failed_channels") return "failed channels";
  if (p == "peak_force_n") return "peak contact force (N)";
  return p;
}

struct MapPair {
  std::string x, y;
};

std::vector<MapPair> map_pairs(const StudySpec& spec) {
  const auto v = varying_parameters(spec);
  std::vector<MapPair> out;
  if (v.size() == 1) out.push_back({v[0], "peak_force_n"});
  for (size_t i = 0; i < v.size() && out.size() < 3; ++i)
    for (size_t j = i + 1; j < v.size() && out.size() < 3; ++j) out.push_back({v[i], v[j]});
  return out;
}

double value_of(const CaseOutcome& o, const std::string& p) {
  if (p == "peak_force_n") return o.result.peak_force_max_n();
  return parameter_value(o.params, p);
}

/// Scatter map: one square per case at (x, y), coloured by `colour(case)`.
/// Cases sharing a point are drawn in order of `rank`, so the worst one is on top.
template <typename Colour, typename Rank>
std::string scatter_svg(const std::string& id, const std::string& title, const StudySummary& s, const MapPair& m,
                        Colour colour, Rank rank, const std::string& legend) {
  const int w = 560, h = 380, l = 78, r = 20, t = 34, b = 56;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const CaseOutcome& o : s.outcomes) {
    if (!o.done) continue;
    const double x = value_of(o, m.x), y = value_of(o, m.y);
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  if (!(x1 >= x0)) x0 = 0, x1 = 1;
  if (!(y1 >= y0)) y0 = 0, y1 = 1;
  if (x1 == x0) x0 -= 0.5 * std::max(1e-12, std::abs(x0)), x1 += 0.5 * std::max(1e-12, std::abs(x1));
  if (y1 == y0) y0 -= 0.5 * std::max(1e-12, std::abs(y0)), y1 += 0.5 * std::max(1e-12, std::abs(y1));
  const double pad_x = 0.04 * (x1 - x0), pad_y = 0.04 * (y1 - y0);
  x0 -= pad_x, x1 += pad_x, y0 -= pad_y, y1 += pad_y;
  auto px = [&](double x) { return l + (x - x0) / (x1 - x0) * (w - l - r); };
  auto py = [&](double y) { return h - b - (y - y0) / (y1 - y0) * (h - t - b); };
  std::string o = "<svg id=\"" + id + "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(w) + "\" height=\"" +
                  std::to_string(h) + "\" viewBox=\"0 0 " + std::to_string(w) + " " + std::to_string(h) + "\">";
  o += "<text x=\"" + std::to_string(w / 2) + "\" y=\"18\" text-anchor=\"middle\" font-size=\"14\">" + rp::escape_xml(title) + "</text>";
  o += "<rect x=\"" + std::to_string(l) + "\" y=\"" + std::to_string(t) + "\" width=\"" + std::to_string(w - l - r) +
       "\" height=\"" + std::to_string(h - t - b) + "\" fill=\"none\" stroke=\"#333\"/>";
  auto ticks = [&](const std::string& p, double lo, double hi, bool is_x) {
    std::vector<std::pair<double, std::string>> tk;
    if (p == "failed_channels") {
      std::set<int> masks;
      for (const CaseOutcome& c : s.outcomes) masks.insert(c.params.failed_channels);
      for (int mk : masks) tk.push_back({static_cast<double>(mk), channels_name(static_cast<std::uint8_t>(mk))});
    } else {
      const auto v = rp::nice_ticks(lo, hi, is_x ? 6 : 5);
      const double step = v.size() > 1 ? v[1] - v[0] : 1.0;
      for (double x : v) tk.push_back({x, rp::format_tick(x, step)});
    }
    std::string out;
    for (const auto& [v, text] : tk) {
      if (v < lo || v > hi) continue;
      if (is_x)
        out += "<line x1=\"" + io::printf_text("%.4g", px(v)) + "\" x2=\"" + io::printf_text("%.4g", px(v)) + "\" y1=\"" + std::to_string(h - b) + "\" y2=\"" +
               std::to_string(h - b + 5) + "\" stroke=\"#333\"/><text x=\"" + io::printf_text("%.4g", px(v)) + "\" y=\"" + std::to_string(h - b + 18) +
               "\" text-anchor=\"middle\" font-size=\"11\">" + rp::escape_xml(text) + "</text>";
      else
        out += "<line x1=\"" + std::to_string(l - 5) + "\" x2=\"" + std::to_string(l) + "\" y1=\"" + io::printf_text("%.4g", py(v)) + "\" y2=\"" +
               io::printf_text("%.4g", py(v)) + "\" stroke=\"#333\"/><text x=\"" + std::to_string(l - 8) + "\" y=\"" + io::printf_text("%.4g", py(v) + 4) +
               "\" text-anchor=\"end\" font-size=\"11\">" + rp::escape_xml(text) + "</text>";
    }
    return out;
  };
  o += ticks(m.x, x0, x1, true) + ticks(m.y, y0, y1, false);
  o += "<text x=\"" + std::to_string((l + w - r) / 2) + "\" y=\"" + std::to_string(h - 14) +
       "\" text-anchor=\"middle\" font-size=\"12\">" + rp::escape_xml(axis_label(m.x)) + "</text>";
  o += "<text transform=\"translate(16 " + std::to_string((t + h - b) / 2) + ") rotate(-90)\" text-anchor=\"middle\" font-size=\"12\">" +
       rp::escape_xml(axis_label(m.y)) + "</text>";
  // Mark size: about one grid cell of a dense sample, at least 3 px.
  const double side = std::clamp(std::sqrt((w - l - r) * (h - t - b) / std::max<double>(1.0, static_cast<double>(s.outcomes.size()))) * 0.5, 3.0, 14.0);
  std::vector<const CaseOutcome*> order;
  for (const CaseOutcome& c : s.outcomes)
    if (c.done) order.push_back(&c);
  std::stable_sort(order.begin(), order.end(), [&](const CaseOutcome* p, const CaseOutcome* q) { return rank(*p) < rank(*q); });
  for (const CaseOutcome* cp : order) {
    const CaseOutcome& c = *cp;
    o += "<rect class=\"case\" x=\"" + io::printf_text("%.4g", px(value_of(c, m.x)) - side / 2) + "\" y=\"" + io::printf_text("%.4g", py(value_of(c, m.y)) - side / 2) +
         "\" width=\"" + io::printf_text("%.4g", side) + "\" height=\"" + io::printf_text("%.4g", side) + "\" fill=\"" + colour(c) + "\" fill-opacity=\"0.85\"><title>case " +
         std::to_string(c.index) + "</title></rect>";
  }
  o += "<text x=\"" + std::to_string(l) + "\" y=\"" + std::to_string(t - 6) + "\" font-size=\"11\">" + rp::escape_xml(legend) + "</text>";
  o += "</svg>";
  return o;
}

std::string worst_table(const StudySummary& s, const std::vector<size_t>& rows, const std::string& id) {
  std::string o = "<table id=\"" + id + "\"><tr><th>case</th><th>speed (Hz)</th><th>friction</th><th>unbalance factor</th>"
                  "<th>clearance (mm)</th><th>offset x, y (um)</th><th>failed</th><th>peak force (N)</th><th>whirl</th>"
                  "<th>friction energy (J)</th><th>life fraction</th></tr>";
  for (size_t k : rows) {
    const CaseOutcome& c = s.outcomes[k];
    o += "<tr><td>" + std::to_string(c.index) + "</td><td>" + io::printf_text("%.4g", c.params.speed_hz) + "</td><td>" + io::printf_text("%.4g", c.params.friction) +
         "</td><td>" + io::printf_text("%.4g", c.params.unbalance_factor) + "</td><td>" + (c.params.clearance_m > 0 ? io::printf_text("%.4g", c.params.clearance_m * 1e3) : "board") +
         "</td><td>" + io::printf_text("%.4g", c.params.offset_x_m * 1e6) + ", " + io::printf_text("%.4g", c.params.offset_y_m * 1e6) + "</td><td>" +
         channels_name(c.params.failed_channels) + "</td><td>" + io::printf_text("%.1f", c.result.peak_force_max_n()) + "</td><td>" +
         c.result.whirl_worst() + "</td><td>" + io::printf_text("%.4g", c.result.friction_energy_total_j()) + "</td><td>" +
         io::printf_text("%.3e", c.result.life_fraction_max()) + "</td></tr>";
  }
  return o + "</table>";
}

}  // namespace

std::vector<std::string> envelope_map_ids(const StudySpec& spec) {
  std::vector<std::string> ids;
  for (const MapPair& m : map_pairs(spec))
    for (const char* k : {"force", "life", "whirl"}) ids.push_back(std::string("map-") + k + "-" + m.x + "-" + m.y);
  return ids;
}

std::string render_envelope_report(const StudySpec& spec, const StudySummary& s) {
  double fmax = 0.0, lmax = 0.0;
  std::map<std::string, int> whirls;
  for (const CaseOutcome& c : s.outcomes) {
    if (!c.done) continue;
    fmax = std::max(fmax, c.result.peak_force_max_n());
    lmax = std::max(lmax, c.result.life_fraction_max());
    ++whirls[c.result.whirl_worst()];
  }
  std::string o =
      "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>Drop envelope: " + rp::escape_xml(spec.source) +
      "</title><style>body{font-family:sans-serif;margin:1.5em;max-width:1200px}table{border-collapse:collapse;margin:.5em 0}"
      "td,th{border:1px solid #bbb;padding:2px 6px;font-size:13px;text-align:right}th{background:#eee}"
      "svg{margin:4px;background:#fff}.maps{display:flex;flex-wrap:wrap}</style></head><body>";
  o += "<h1>Drop envelope</h1><section id=\"facts\"><table>";
  auto row = [&](const std::string& k, const std::string& v) { o += "<tr><th>" + k + "</th><td>" + rp::escape_xml(v) + "</td></tr>"; };
  row("spec", spec.source);
  row("board", spec.settings.board);
  row("method", spec.method == "lhs" ? "Latin hypercube, seed " + std::to_string(spec.seed) : "grid");
  row("cases", std::to_string(s.cases) + " (" + std::to_string(s.cases_run) + " simulated, " + std::to_string(s.cases_reused) +
                   " reused, " + std::to_string(s.cases_failed) + " failed)");
  row("drop", "levitated " + io::printf_text("%.4g", spec.settings.settle_s) + " s, then " + io::printf_text("%.4g", spec.settings.window_s) + " s after the cut; step " +
                  io::printf_text("%.4g", spec.settings.step_s) + " s; contact law " + spec.settings.contact_law);
  row("life model", "friction-energy budget " + io::printf_text("%.0f", spec.settings.friction_energy_budget_j) + " J per aux bearing");
  std::string wl;
  for (const auto& [k, n] : whirls) wl += (wl.empty() ? "" : ", ") + k + " " + std::to_string(n);
  row("whirl (worse bearing)", wl);
  row("largest peak force", io::printf_text("%.1f", fmax) + " N");
  row("largest life fraction per drop", io::printf_text("%.3e", lmax));
  o += "</table></section><section id=\"maps\"><h2>Maps</h2><div class=\"maps\">";
  for (const MapPair& m : map_pairs(spec)) {
    const std::string suffix = m.x + "-" + m.y;
    o += scatter_svg(
        "map-force-" + suffix, "peak contact force", s, m,
        [&](const CaseOutcome& c) { return ramp(fmax > 0 ? c.result.peak_force_max_n() / fmax : 0.0); },
        [](const CaseOutcome& c) { return c.result.peak_force_max_n(); },
        "colour: 0 (blue) .. " + io::printf_text("%.0f", fmax) + " N (red)");
    o += scatter_svg(
        "map-life-" + suffix, "life fraction per drop", s, m,
        [&](const CaseOutcome& c) { return ramp(lmax > 0 ? c.result.life_fraction_max() / lmax : 0.0); },
        [](const CaseOutcome& c) { return c.result.life_fraction_max(); },
        "colour: 0 (blue) .. " + io::printf_text("%.2e", lmax) + " (red)");
    o += scatter_svg(
        "map-whirl-" + suffix, "whirl type", s, m, [&](const CaseOutcome& c) { return std::string(whirl_colour(c.result.whirl_worst())); },
        [](const CaseOutcome& c) { return static_cast<double>(whirl_rank(c.result.whirl_worst())); },
        "grey none, blue bouncing, orange forward, red backward");
  }
  if (map_pairs(spec).empty()) o += "<p id=\"maps-na\">not available: no parameter varies in this study</p>";
  o += "</div></section><section id=\"worst\"><h2>Worst cases: peak contact force</h2>" + worst_table(s, s.worst_force, "worst-force");
  o += "<h2>Worst cases: life fraction</h2>" + worst_table(s, s.worst_life, "worst-life") + "</section>";
  if (s.cases_failed > 0) {
    o += "<section id=\"failed\"><h2>Failed cases</h2><ul>";
    for (const CaseOutcome& c : s.outcomes)
      if (!c.done) o += "<li>case " + std::to_string(c.index) + ": " + rp::escape_xml(c.error) + "</li>";
    o += "</ul></section>";
  }
  return o + "</body></html>\n";
}

}  // namespace amb::host::envelope
