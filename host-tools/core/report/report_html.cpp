#include "host-tools/core/report/report_html.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/page_file.hpp"
#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::report {

namespace {
const char* const k_state_colour[4] = {"#ffffff", "#2ca02c", "#ff7f0e", "#d62728"};
const char* const k_state_name[4] = {"no contact", "swinging", "forward rub", "backward rub"};

std::string plane_key(size_t i) { return i == 0 ? "a" : "b"; }

// --- what is drawn, by id (shared by the renderer and plot_ids) -------------------------
struct Plan {
  std::vector<std::string> ids, na;
};

Plan plan(const ReportData& d) {
  Plan p;
  auto na = [&](bool available, const char* id) {
    if (!available) p.na.push_back(id);
  };
  na(d.replay.available(), "replay-na");
  if (d.orbit.available())
    for (size_t i = 0; i < d.orbit.data->size(); ++i) p.ids.push_back("orbit-" + plane_key(i));
  na(d.orbit.available(), "orbit-na");
  if (d.rubbing.available())
    for (size_t i = 0; i < d.rubbing.data->size(); ++i) {
      p.ids.push_back("contact-angle-" + plane_key(i));
      p.ids.push_back("contact-slope-" + plane_key(i));
    }
  na(d.rubbing.available(), "rubbing-na");
  if (d.speed.available()) p.ids.push_back("speed");
  na(d.speed.available(), "speed-na");
  if (d.forces.available()) p.ids.push_back("contact-forces");
  na(d.forces.available(), "forces-na");
  if (d.load.available())
    for (size_t i = 0; i < 2; ++i)
      if (!d.load.data->event_n[i].empty() || !d.load.data->cumulative_n[i].empty()) p.ids.push_back("load-" + plane_key(i));
  na(d.load.available(), "load-na");
  if (d.fit.available()) p.ids.push_back("fit-convergence");
  na(d.fit.available(), "fit-na");
  if (d.residual.available())
    for (size_t i = 0; i < d.residual.data->size(); ++i) p.ids.push_back("residual-spectrum-" + std::to_string(i));
  na(d.residual.available(), "residual-na");
  na(d.drop_residual.available(), "drop-residual-na");
  na(d.wear.available(), "wear-na");
  return p;
}

std::string table(const std::vector<std::pair<std::string, std::string>>& rows, const char* cls = "facts") {
  std::string s = std::string("<table class=\"") + cls + "\">\n";
  for (const auto& [k, v] : rows) s += "<tr><th>" + escape_xml(k) + "</th><td>" + escape_xml(v) + "</td></tr>\n";
  return s + "</table>\n";
}

// The two bearings' tables side by side, each headed "<label> A" or "<label> B" (an empty one
// is left out).
std::string bearing_tables(const std::array<std::vector<std::pair<std::string, std::string>>, 2>& bearing, const char* label) {
  std::string s = "<div class=\"row\">\n";
  for (size_t b = 0; b < 2; ++b)
    if (!bearing[b].empty()) s += std::string("<div><h3>") + label + (b ? " B" : " A") + "</h3>" + table(bearing[b]) + "</div>\n";
  return s + "</div>\n";
}

std::string not_available(const char* id, const std::string& why) {
  return std::string("<div class=\"na\" id=\"") + id + "\"><b>not available:</b> " + escape_xml(why) + "</div>\n";
}

// A plot over the event's time axis (time from the trigger, s): the rubbing, speed and
// force sections draw theirs on the same axis.
LinePlot time_plot(std::string id, std::string title, std::string y_label, int width_px) {
  LinePlot p;
  p.id = std::move(id);
  p.title = std::move(title);
  p.x_label = "time from trigger (s)";
  p.y_label = std::move(y_label);
  p.width_px = width_px;
  return p;
}

std::string source_line(const std::string& src) {
  return src.empty() ? std::string() : "<p class=\"src\">source: " + escape_xml(src) + "</p>\n";
}

/// Contiguous runs of equal non-zero state as shaded intervals.
std::vector<Interval> state_intervals(const RubbingTrace& r) {
  std::vector<Interval> out;
  const size_t n = std::min(r.t_s.size(), r.state.size());
  size_t i = 0;
  while (i < n) {
    const int s = r.state[i];
    size_t j = i;
    while (j + 1 < n && r.state[j + 1] == s) ++j;
    if (s > 0 && s < 4) {
      const double half = n > 1 ? 0.5 * (r.t_s[1] - r.t_s[0]) : 0.0;
      out.push_back({r.t_s[i] - half, r.t_s[j] + half, k_state_name[s], k_state_colour[s]});
    }
    i = j + 1;
  }
  return out;
}

std::string section_orbit(const ReportData& d) {
  std::string s = "<section id=\"orbit\"><h2>Orbit at the bearing planes</h2>\n";
  if (!d.orbit.available()) return s + not_available("orbit-na", d.orbit.why_not) + "</section>\n";
  s += "<div class=\"row\">\n";
  for (size_t i = 0; i < d.orbit.data->size(); ++i) {
    const OrbitPlane& o = (*d.orbit.data)[i];
    LinePlot p;
    p.id = "orbit-" + plane_key(i);
    p.title = "Orbit, " + o.name;
    p.x_label = "x (\u00b5m)";
    p.y_label = "y (\u00b5m)";
    p.equal_aspect = true;
    p.width_px = 520;
    p.height_px = 420;
    auto um = [](const std::vector<double>& v) {
      std::vector<double> o2(v.size());
      for (size_t k = 0; k < v.size(); ++k) o2[k] = v[k] * 1e6;
      return o2;
    };
    Series sp{"sensor plane", um(o.sensor_x_m), um(o.sensor_y_m), palette(0), 1.0, false, true};
    p.series.push_back(sp);
    // Dashed: not measured but extrapolated (rigid rotor); the caption says so.
    if (!o.aux_x_m.empty()) p.series.push_back({"aux plane (rigid)", um(o.aux_x_m), um(o.aux_y_m), palette(1), 1.0, true, true});
    if (!o.truth_x_m.empty()) p.series.push_back({"aux plane (plant)", um(o.truth_x_m), um(o.truth_y_m), palette(2), 1.0, false, true});
    if (o.clearance_m > 0.0) p.circles.push_back({0.0, 0.0, o.clearance_m * 1e6, "clearance " + io::printf_text("%.0f \u00b5m", o.clearance_m * 1e6)});
    s += render_line_plot(p);
  }
  return s + "</div>\n<p class=\"caption\">The aux-plane orbit (dashed) is not measured: it is extrapolated from the two "
             "sensor planes as if the rotor were rigid. The rotor bends during the drop, so it can pass the clearance "
             "circle although the journal cannot. Where the run is simulated, the plant's own aux-plane orbit is drawn "
             "too and the extrapolation's error is in Figures; otherwise the error is not known.</p>\n" +
         source_line(d.orbit.source) + "</section>\n";
}

std::string section_figures(const ReportData& d) {
  std::string s = "<section id=\"figures\"><h2>Figures and their definitions</h2>\n";
  if (!d.cause_chain.empty()) {
    s += "<p id=\"cause-chain\"><b>Cause chain:</b> ";
    for (size_t i = 0; i < d.cause_chain.size(); ++i) s += (i ? " &rarr; " : "") + escape_xml(d.cause_chain[i]);
    s += "</p>\n";
  }
  if (d.figures.empty()) return s + "</section>\n";
  s += "<p class=\"caption\">Each figure is defined once here; the sections quote it under the same name.</p>\n";
  s += "<table class=\"facts figures\">\n<tr><th>figure</th><td>value</td><td class=\"def\">definition</td></tr>\n";
  for (const Figure& f : d.figures)
    s += "<tr><th>" + escape_xml(f.name) + "</th><td>" + escape_xml(f.value) + "</td><td class=\"def\">" + escape_xml(f.definition) +
         "</td></tr>\n";
  return s + "</table>\n</section>\n";
}

std::string section_rubbing(const ReportData& d) {
  std::string s = "<section id=\"rubbing\"><h2>Contact polar angle, its slope and the rubbing states</h2>\n";
  if (!d.rubbing.available()) return s + not_available("rubbing-na", d.rubbing.why_not) + "</section>\n";
  for (size_t i = 0; i < d.rubbing.data->size(); ++i) {
    const RubbingTrace& r = (*d.rubbing.data)[i];
    const auto bands = state_intervals(r);
    s += "<div class=\"row\">\n";
    LinePlot a = time_plot("contact-angle-" + plane_key(i), "Whirl angle, " + r.name, "angle, unwrapped (deg)", 600);
    a.series.push_back({"whirl angle", r.t_s, r.angle_deg, palette(0)});
    a.intervals = bands;
    s += render_line_plot(a);
    LinePlot b = time_plot("contact-slope-" + plane_key(i), "Whirl rate, " + r.name, "slope (rev/s)", 600);
    b.series.push_back({"slope", r.t_s, r.slope_hz, palette(4)});
    b.intervals = bands;
    s += render_line_plot(b);
    s += "</div>\n";
    if (!r.rows.empty()) s += table(r.rows);
    else
      s += "<p>" + escape_xml(r.name) + ": swinging " + io::printf_text("%.3f s", r.durations_s[0]) + ", forward rub " +
           io::printf_text("%.3f s", r.durations_s[1]) + ", backward rub " + io::printf_text("%.3f s", r.durations_s[2]) + "</p>\n";
  }
  return s + source_line(d.rubbing.source) + "</section>\n";
}

std::string section_speed(const ReportData& d) {
  std::string s = "<section id=\"speed-section\"><h2>Speed</h2>\n";
  if (!d.speed.available()) return s + not_available("speed-na", d.speed.why_not) + "</section>\n";
  LinePlot p = time_plot("speed", "Rotor speed", "speed (Hz)", 900);
  p.series.push_back({d.speed.data->speed_label, d.speed.data->t_s, d.speed.data->speed_hz, palette(0)});
  if (!d.speed.data->speed_command_hz.empty())
    p.series.push_back({"drive command", d.speed.data->t_s, d.speed.data->speed_command_hz, palette(3), 1.2, true});
  const auto& sp = *d.speed.data;
  bool any_plant = false;
  for (double v : sp.plant_speed_hz) any_plant |= std::isfinite(v);
  if (any_plant) p.series.push_back({"tachometer", sp.t_s, sp.plant_speed_hz, palette(2), 1.2});
  // Spans where the board had no valid speed: shaded, one band per run of lost samples.
  for (size_t i = 0; i < sp.not_tracked.size() && i < sp.t_s.size();) {
    if (!sp.not_tracked[i]) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j + 1 < sp.not_tracked.size() && j + 1 < sp.t_s.size() && sp.not_tracked[j + 1]) ++j;
    p.intervals.push_back({sp.t_s[i], sp.t_s[j], "not tracked", "#bbbbbb"});
    i = j + 1;
  }
  return s + render_line_plot(p) + source_line(d.speed.source) + "</section>\n";
}

std::string section_forces(const ReportData& d) {
  std::string s = "<section id=\"forces\"><h2>Contact forces</h2>\n";
  if (!d.forces.available()) return s + not_available("forces-na", d.forces.why_not) + "</section>\n";
  LinePlot p = time_plot("contact-forces", "Contact forces at the auxiliary bearings", "force (N)", 900);
  const ForceTrace& f = *d.forces.data;
  for (size_t b = 0; b < 2; ++b) {
    if (!f.normal_n[b].empty()) p.series.push_back({"normal " + std::string(b ? "B" : "A"), f.t_s, f.normal_n[b], palette(b)});
    if (!f.friction_n[b].empty())
      p.series.push_back({"friction " + std::string(b ? "B" : "A"), f.t_s, f.friction_n[b], palette(b), 1.0, true});
  }
  return s + render_line_plot(p) + source_line(d.forces.source) + "</section>\n";
}

std::string section_load(const ReportData& d) {
  std::string s = "<section id=\"load\"><h2>Load over the bearing circumference</h2>\n";
  if (!d.load.available()) return s + not_available("load-na", d.load.why_not) + "</section>\n";
  s += "<div class=\"row\">\n";
  const LoadMap& m = *d.load.data;
  for (size_t b = 0; b < 2; ++b) {
    if (m.event_n[b].empty() && m.cumulative_n[b].empty()) continue;
    PolarPlot p;
    p.id = "load-" + plane_key(b);
    p.title = std::string("Load, bearing ") + (b ? "B" : "A");
    p.r_label = "sum of contact forces per 1\u00b0 bin (N)";
    auto polar = [](const std::vector<double>& v) {
      std::vector<double> a(v.size());
      for (size_t k = 0; k < v.size(); ++k) a[k] = static_cast<double>(k) + 0.5;
      return a;
    };
    if (!m.cumulative_n[b].empty()) p.series.push_back({"cumulative", polar(m.cumulative_n[b]), m.cumulative_n[b], palette(7)});
    // This event as an outline over the filled cumulative load: overlapping fills would make
    // a colour that is in neither legend entry.
    if (!m.event_n[b].empty()) p.series.push_back({"this event", polar(m.event_n[b]), m.event_n[b], palette(1), false});
    s += render_polar_plot(p);
  }
  return s + "</div>\n" + source_line(d.load.source) + "</section>\n";
}

std::string section_fit(const ReportData& d) {
  std::string s = "<section id=\"fit\"><h2>Fit convergence (Phase C)</h2>\n";
  if (!d.fit.available()) return s + not_available("fit-na", d.fit.why_not) + "</section>\n";
  const FitConvergence& f = *d.fit.data;
  LinePlot p;
  p.id = "fit-convergence";
  p.title = "Best cost per iteration";
  p.x_label = "iteration (0: design of experiments)";
  p.y_label = "cost";
  p.log_y = true;
  std::vector<double> it(f.cost_history.size());
  for (size_t k = 0; k < it.size(); ++k) it[k] = static_cast<double>(k);
  p.series.push_back({"best cost", it, f.cost_history, palette(0), 1.8});
  std::vector<std::pair<std::string, std::string>> rows{
      {"friction coefficient", io::printf_text("%.4f", f.friction_coefficient)},
      {"converged", f.converged ? "yes" : "no"},
      {"evaluations", std::to_string(f.evaluations)},
      {"wall time", io::printf_text("%.2f s", f.wall_s)},
      {"stop reason", f.stop_reason}};
  for (const auto& [k, v] : f.figures) rows.emplace_back(k, io::printf_text("%.6g", v));
  rows.insert(rows.end(), f.rows.begin(), f.rows.end());
  return s + "<div class=\"row\">" + render_line_plot(p) + table(rows) + "</div>\n" + source_line(d.fit.source) + "</section>\n";
}

std::string section_residual(const ReportData& d) {
  std::string s = "<section id=\"residual\"><h2>Residual spectra before and after each added effect</h2>\n";
  if (!d.residual.available()) return s + not_available("residual-na", d.residual.why_not) + "</section>\n";
  for (size_t i = 0; i < d.residual.data->size(); ++i) {
    const ResidualSpectra& r = (*d.residual.data)[i];
    LinePlot p;
    p.id = "residual-spectrum-" + std::to_string(i);
    p.title = "Spectra, " + r.channel;
    p.x_label = "frequency (Hz)";
    p.y_label = "PSD (" + r.unit + ")";
    p.log_y = true;
    p.width_px = 900;
    p.series.push_back({"measured", r.f_hz, r.measured, "#000000", 1.6});
    // The last model step first, the base model (dashed) over it: where they coincide the
    // dashes still show the base model.
    for (size_t k = r.model_steps.size(); k-- > 0;)
      p.series.push_back({r.model_steps[k].first, r.f_hz, r.model_steps[k].second, palette(k + 1), k == 0 ? 2.0 : 1.3, k == 0});
    s += render_line_plot(p);
    if (!r.figures.empty()) s += table(r.figures);
  }
  return s + source_line(d.residual.source) + "</section>\n";
}

std::string section_drop_residual(const ReportData& d) {
  std::string s = "<section id=\"drop-residual\"><h2>Residual loop on a drop event</h2>\n";
  if (!d.drop_residual.available()) return s + not_available("drop-residual-na", d.drop_residual.why_not) + "</section>\n";
  const DropResidualSummary& r = *d.drop_residual.data;
  return s + table(r.rows) + bearing_tables(r.bearing, "Aux bearing") + source_line(d.drop_residual.source) + "</section>\n";
}

std::string section_wear(const ReportData& d) {
  std::string s = "<section id=\"wear\"><h2>Wear record</h2>\n";
  if (!d.wear.available()) return s + not_available("wear-na", d.wear.why_not) + "</section>\n";
  const WearSummary& w = *d.wear.data;
  return s + table(w.rows) + bearing_tables(w.bearing, "Bearing") + source_line(d.wear.source) + "</section>\n";
}

std::string section_quick_look(const ReportData& d) {
  std::string s = "<section id=\"quick-look\"><h2>Board quick-look aux-bearing load</h2>\n";
  if (!d.quick_look.available()) return s + not_available("quick-look-na", d.quick_look.why_not) + "</section>\n";
  const QuickLookSummary& q = *d.quick_look.data;
  if (!q.superseded_by.empty())
    s += "<p class=\"src\">Superseded by " + escape_xml(q.superseded_by) + ": the host's fit is the wear estimate of record.</p>\n";
  return s + table(q.rows) + bearing_tables(q.bearing, "Aux bearing") + source_line(d.quick_look.source) + "</section>\n";
}

std::string section_replay(const ReportData& d) {
  std::string s = "<section id=\"replay\"><h2>Replay through the firmware</h2>\n";
  if (!d.replay.available()) return s + not_available("replay-na", d.replay.why_not) + "</section>\n";
  s += std::string("<p class=\"verdict ") + (d.replay.data->reproduced ? "ok\">reproduced" : "bad\">NOT reproduced") + "</p>\n";
  return s + table(d.replay.data->rows) + source_line(d.replay.source) + "</section>\n";
}

const char* k_css = R"(table.figures td.def{font-family:sans-serif;font-size:12px;color:#555}
.na{background:#fff6e0;border:1px solid #e0b050;padding:10px 14px;margin:8px 0;border-radius:4px}
.src{color:#666;font-size:12px}.verdict{font-weight:bold;font-size:18px}.ok{color:#1a7f1a}.bad{color:#b00})";
}  // namespace

std::vector<std::string> plot_ids(const ReportData& d) { return plan(d).ids; }
std::vector<std::string> unavailable_ids(const ReportData& d) { return plan(d).na; }

std::string render_event_report(const ReportData& d) {
  std::string s = page_head(d.title, k_css);
  s += "<h1>" + escape_xml(d.title) + "</h1>\n<p class=\"sub\">" + escape_xml(d.subtitle) + "</p>\n";
  s += "<section id=\"facts\"><h2>Event</h2>\n" + table(d.facts.rows) + "</section>\n";
  // The sections, in page order.
  using Section = std::string (*)(const ReportData&);
  const Section sections[] = {section_figures, section_replay,   section_orbit,         section_rubbing,
                              section_speed,   section_forces,   section_load,          section_fit,
                              section_residual, section_drop_residual, section_wear,   section_quick_look};
  for (const Section section : sections) s += section(d);
  if (!d.notes.empty()) {
    s += "<section id=\"notes\"><h2>Notes</h2>\n<ul>\n";
    for (const auto& n : d.notes) s += "<li>" + escape_xml(n) + "</li>\n";
    s += "</ul>\n</section>\n";
  }
  s += "<footer>" + escape_xml(d.generated_by) + "</footer>\n</body>\n</html>\n";
  return s;
}

std::string write_event_report(const ReportData& d, const std::string& path) {
  return write_page_file(render_event_report(d), path, "report", " (check the directory exists and is writable, or pass --out FILE)");
}

}  // namespace amb::host::report
