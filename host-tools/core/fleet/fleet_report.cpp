#include "host-tools/core/fleet/fleet_report.hpp"

#include <cstdio>
#include <map>
#include <algorithm>
#include <set>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::fleet {
namespace {

namespace rp = amb::host::report;

std::string bearing_name(int b) { return "aux " + std::to_string(b + 1); }

}  // namespace

std::string render_fleet_page(const FleetPageData& d) {
  std::int64_t events = 0;
  for (const auto& m : d.machines) events += m.events;
  std::string o =
      "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>Fleet: aux-bearing life</title><style>"
      "body{font-family:sans-serif;margin:1.5em;max-width:1200px}table{border-collapse:collapse;margin:.5em 0}"
      "td,th{border:1px solid #bbb;padding:2px 8px;font-size:13px}th{background:#eee}td.n{text-align:right}"
      ".bar{display:inline-block;height:10px;background:#c0392b}.bar.ok{background:#27ae60}.bar.warn{background:#e67e22}"
      "</style></head><body><h1>Fleet: auxiliary-bearing life</h1>";
  o += "<p id=\"facts\">store " + rp::escape_xml(d.store) + ": " + std::to_string(d.machines.size()) + " machines, " +
       std::to_string(events) + " events</p>";

  o += "<h2>Bearings nearest their budget</h2>";
  if (d.nearest.empty()) {
    o += "<p id=\"nearest-na\">not available: no event or wear record stored</p>";
  } else {
    o += "<table id=\"nearest\"><tr><th>machine</th><th>bearing</th><th>life used</th><th></th><th>source</th><th>peak force (N)</th>"
         "<th>events</th></tr>";
    for (const BearingStatus& s : d.nearest) {
      const double pct = 100.0 * s.life_used_fraction;
      const char* cls = s.life_used_fraction >= 0.8 ? "bar" : s.life_used_fraction >= 0.5 ? "bar warn" : "bar ok";
      o += "<tr><td>" + rp::escape_xml(s.machine) + "</td><td>" + bearing_name(s.bearing) + "</td><td class=\"n\">" + io::printf_text("%.2f", pct) +
           " %</td><td><span class=\"" + cls + "\" style=\"width:" + io::printf_text("%.1f", std::min(100.0, std::max(0.0, pct)) * 2.0) +
           "px\"></span></td><td>" + (s.source == "wear" ? "wear record" : "quick-look (no wear record)") + "</td><td class=\"n\">" +
           io::printf_text("%.1f", s.peak_force_n) + "</td><td class=\"n\">" + std::to_string(s.events) + "</td></tr>";
    }
    o += "</table>";
  }

  o += "<h2>Life used over time</h2>";
  // One curve per bearing, the source the standing uses; nearest bearings first.
  std::map<std::pair<std::string, int>, std::string> chosen;
  for (const BearingStatus& s : d.nearest)
    if (static_cast<int>(chosen.size()) < d.max_curves) chosen[{s.machine, s.bearing}] = s.source;
  std::map<std::pair<std::string, int>, rp::Series> curves;
  for (const TrendPoint& p : d.trend) {
    const auto key = std::make_pair(p.machine, p.bearing);
    const auto it = chosen.find(key);
    if (it == chosen.end() || it->second != p.source) continue;
    rp::Series& s = curves[key];
    s.label = p.machine + " " + bearing_name(p.bearing);
    s.x.push_back(static_cast<double>(p.order));
    s.y.push_back(100.0 * p.life_used_fraction);
  }
  if (curves.empty()) {
    o += "<p id=\"trend-na\">not available: no life figures stored</p>";
  } else {
    rp::LinePlot plot;
    plot.id = "trend";
    plot.title = "life used per aux bearing";
    plot.x_label = "wear-record sequence / event number";
    plot.y_label = "life used (%)";
    plot.width_px = 900;
    plot.height_px = 420;
    for (auto& [k, s] : curves) plot.series.push_back(std::move(s));
    o += rp::render_line_plot(plot);
  }

  o += "<h2>Machines</h2><table id=\"machines\"><tr><th>machine</th><th>rig</th><th>events</th><th>last event</th>"
       "<th>wear records</th><th>fits</th><th>residual results</th></tr>";
  for (const MachineSummary& m : d.machines)
    o += "<tr><td>" + rp::escape_xml(m.name) + "</td><td>" + rp::escape_xml(m.rig) + "</td><td class=\"n\">" + std::to_string(m.events) +
         "</td><td class=\"n\">" + (m.last_event_number < 0 ? std::string("-") : std::to_string(m.last_event_number)) +
         "</td><td class=\"n\">" + std::to_string(m.wear_records) + "</td><td class=\"n\">" + std::to_string(m.fits) +
         "</td><td class=\"n\">" + std::to_string(m.residuals) + "</td></tr>";
  o += "</table></body></html>\n";
  return o;
}

}  // namespace amb::host::fleet
