#include "host-tools/core/report/sweep_page.hpp"

#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/page_file.hpp"
#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::report {
namespace {

using cd = std::complex<double>;
using sweep::SweepAnalysis;

const char* k_css = R"(table.grid{border-collapse:collapse;margin:8px 0}table.grid th,table.grid td{border:1px solid #ccc;padding:3px 8px;text-align:left}
table.grid td{font-family:monospace}
.zone-A{background:#d9f2d9}.zone-B{background:#eef7c8}.zone-C{background:#ffe9c2}.zone-D{background:#f8cccc})";

std::string num(const char* fmt, double v) { return io::printf_text(fmt, v); }

double db(cd z) { return 20.0 * std::log10(std::abs(z)); }
double deg(cd z) { return std::arg(z) * 180.0 / M_PI; }

std::string facts(const std::vector<std::pair<std::string, std::string>>& rows) {
  std::string s = "<table class=\"facts\">\n";
  for (const auto& [k, v] : rows) s += "<tr><th>" + escape_xml(k) + "</th><td>" + escape_xml(v) + "</td></tr>\n";
  return s + "</table>\n";
}

std::string grid(const std::vector<std::string>& head, const std::vector<std::vector<std::string>>& rows, const std::string& id,
                 const std::vector<std::string>& row_class = {}) {
  std::string s = "<table class=\"grid\" id=\"" + id + "\">\n<tr>";
  for (const auto& h : head) s += "<th>" + escape_xml(h) + "</th>";
  s += "</tr>\n";
  for (size_t r = 0; r < rows.size(); ++r) {
    s += r < row_class.size() && !row_class[r].empty() ? "<tr class=\"" + row_class[r] + "\">" : "<tr>";
    for (const auto& c : rows[r]) s += "<td>" + escape_xml(c) + "</td>";
    s += "</tr>\n";
  }
  return s + "</table>\n";
}

std::string key(int axis) { return sweep::axis_name(axis); }

// Which function of a line: 0 S, 1 T, 2 G.
const sweep::TransferEstimate& meas(const sweep::LineEstimate& l, int k) { return k == 0 ? l.s : k == 1 ? l.t : l.g; }
cd model_of(const sweep::ModelResponse& m, int k) { return k == 0 ? m.s : k == 1 ? m.t : m.g; }

std::string bode(const SweepAnalysis& a, size_t i, int k, bool phase) {
  static const char* names[3] = {"s", "t", "g"};
  static const char* titles[3] = {"sensitivity S = u / e", "complementary sensitivity T = -u_c / e", "plant G = y / u"};
  const auto& ax = a.measured.axes[i];
  LinePlot p;
  p.id = std::string("sweep-") + names[k] + (phase ? "-phase-" : "-mag-") + key(ax.axis);
  p.title = key(ax.axis) + ": " + titles[k] + (phase ? ", phase" : ", magnitude");
  p.x_label = "frequency (Hz)";
  p.y_label = phase ? "phase (deg)" : (k == 2 ? "|G| (dB re 1 m/A)" : "magnitude (dB)");
  p.width_px = 620;
  p.height_px = 300;
  p.log_x = true;
  Series m{"measured", {}, {}, "#000000", 1.6};
  Series b{"board model", {}, {}, "#1f77b4", 1.3, true};
  Series f{"model with " + a.residual.verdict, {}, {}, "#d62728", 1.3};
  Band band{"measured " + num("%.0f", 100.0 * 0.95) + " % band", {}, {}, {}, "#888888"};
  const bool after = a.residual_done && a.residual.verdict != "none" && i < a.residual.after.lines.size();
  for (size_t l = 0; l < ax.lines.size(); ++l) {
    const auto& t = meas(ax.lines[l], k);
    const double fx = ax.lines[l].f_hz;
    m.x.push_back(fx);
    b.x.push_back(fx);
    f.x.push_back(fx);
    const cd mo = model_of(a.model[i][l], k);
    if (phase) {
      m.y.push_back(deg(t.h));
      b.y.push_back(deg(mo));
      if (after) f.y.push_back(deg(model_of(a.residual.after.lines[i][l], k)));
    } else {
      m.y.push_back(db(t.h));
      b.y.push_back(db(mo));
      if (after) f.y.push_back(db(model_of(a.residual.after.lines[i][l], k)));
      band.x.push_back(fx);
      band.lo.push_back(t.mag_lo > 0.0 ? 20.0 * std::log10(t.mag_lo) : std::numeric_limits<double>::quiet_NaN());
      band.hi.push_back(20.0 * std::log10(t.mag_hi));
    }
  }
  p.series = {m, b};
  if (after) p.series.push_back(f);
  if (!phase && k != 1) p.bands.push_back(band);
  if (phase) p.y_range = std::array<double, 2>{-180.0, 180.0};
  return render_line_plot(p);
}

std::string coherence_plot(const SweepAnalysis& a, size_t i) {
  const auto& ax = a.measured.axes[i];
  LinePlot p;
  p.id = "sweep-coherence-" + key(ax.axis);
  p.title = key(ax.axis) + ": coherence";
  p.x_label = "frequency (Hz)";
  p.y_label = "coherence (1)";
  p.log_x = true;
  p.width_px = 620;
  p.height_px = 300;
  Series s{"S (e vs u)", {}, {}, "#000000", 1.6};
  Series g{"G (u vs y)", {}, {}, "#2ca02c", 1.3};
  for (const auto& l : ax.lines) {
    s.x.push_back(l.f_hz);
    s.y.push_back(l.s.coherence);
    g.x.push_back(l.f_hz);
    g.y.push_back(l.g.coherence);
  }
  p.series = {s, g};
  p.y_range = std::array<double, 2>{0.0, 1.0};
  return render_line_plot(p);
}

}  // namespace

std::vector<std::string> sweep_plot_ids(const SweepAnalysis& a) {
  std::vector<std::string> ids;
  for (const auto& ax : a.measured.axes) {
    for (const char* n : {"s", "t", "g"}) {
      ids.push_back(std::string("sweep-") + n + "-mag-" + key(ax.axis));
      ids.push_back(std::string("sweep-") + n + "-phase-" + key(ax.axis));
    }
    ids.push_back("sweep-coherence-" + key(ax.axis));
  }
  return ids;
}

std::string render_sweep_page(const SweepAnalysis& a) {
  const std::string title = "Loop sweep " + a.board_name;
  std::string s = page_head(title, k_css);
  s += "<h1>" + escape_xml(title) + "</h1>\n<p class=\"sub\">ISO 14839-3 sensitivity sweep measured on the board's own loop, "
       "the board's model beside it</p>\n";
  const auto& pl = a.plan;
  s += "<section id=\"facts\"><h2>Sweep</h2>\n" +
       facts({{"board", a.board_name},
              {"rig", a.rig_name},
              {"loop rate", num("%.6g Hz", a.rate_hz)},
              {"rotor speed", num("%.4g Hz", a.speed_hz)},
              {"injection", "controller output (u = u_c + e)"},
              {"excitation", std::string(pl.kind == sweep::ExcitationKind::multisine ? "multisine" : "stepped sine") +
                                 io::printf_text(", %zu lines %.4g-%.4g Hz, %u samples per period, %u periods averaged",
                                                 pl.frequencies_hz.size(), pl.frequencies_hz.empty() ? 0.0 : pl.frequencies_hz.front(),
                                                 pl.frequencies_hz.empty() ? 0.0 : pl.frequencies_hz.back(), pl.samples_per_period,
                                                 pl.recorded_periods)},
              {"amplitude", io::printf_text("%.4g A peak, crest factor %.3g", pl.amplitude_a, pl.crest_factor)},
              {"aborted", a.aborted ? "yes: " + a.abort_reason : "no"},
              {"confidence band", a.measured.band_basis}}) +
       "</section>\n";
  // Zone table.
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> cls;
  for (const auto& z : a.zones) {
    rows.push_back({z.axis_name, z.measured.found ? z.measured.zone : "-",
                    z.measured.found ? io::printf_text("%.3g [%.3g, %.3g]", z.measured.peak, z.measured.lo, z.measured.hi) : "-",
                    z.measured.found ? num("%.4g", z.measured.frequency_hz) : "-",
                    z.measured.found ? num("%.1f", 20.0 * std::log10(z.measured.peak)) : "-",
                    io::printf_text("%s, %.3g at %.4g Hz", z.model_zone.c_str(), z.model_peak, z.model_peak_hz),
                    num("%+.1f %%", z.peak_error_pct)});
    cls.push_back(z.measured.found ? "zone-" + z.measured.zone : "");
  }
  s += "<section id=\"zones\"><h2>ISO 14839-3 zones</h2>\n<p class=\"caption\">Zone of the peak of |S| per control axis "
       "(ISO 14839-3: A below 3 (9.5 dB), newly commissioned; B to 4 (12 dB), unrestricted long-term operation; C to 5 (14 dB), "
       "restricted operation; D above, damage may occur). Measured peak over the lines whose S coherence reaches the floor, "
       "with its confidence band.</p>\n" +
       grid({"axis", "zone", "measured peak |S| [band]", "at (Hz)", "peak (dB)", "board model: zone, peak", "measured vs model"},
            rows, "zone-table", cls) +
       "</section>\n";
  // Residual loop.
  s += "<section id=\"residual\"><h2>Model against the measurement</h2>\n";
  if (a.residual_done) {
    const auto& b = a.residual.before;
    const auto& f = a.residual.after;
    std::vector<std::vector<std::string>> er;
    er.push_back({"board model", num("%.2f", b.s_db_rms), num("%.2f", b.g_db_rms), num("%.4g", b.misfit)});
    if (a.residual.update.kept)
      er.push_back({io::printf_text("updated (force scale %.3f)", a.residual.update.force_scale), num("%.2f", a.residual.updated.s_db_rms),
                    num("%.2f", a.residual.updated.g_db_rms), num("%.4g", a.residual.updated.misfit)});
    er.push_back({"with " + a.residual.verdict, num("%.2f", f.s_db_rms), num("%.2f", f.g_db_rms), num("%.4g", f.misfit)});
    s += "<p class=\"caption\">Residual loop verdict: <b>" + escape_xml(a.residual.verdict) + "</b></p>\n" +
         grid({"model", "S error (dB rms)", "G error (dB rms)", "weighted misfit"}, er, "error-table");
    std::vector<std::vector<std::string>> zr;
    for (size_t i = 0; i < a.zones.size() && i < f.model_zone.size(); ++i)
      zr.push_back({a.zones[i].axis_name, a.zones[i].measured.zone, io::printf_text("%s (%.3g)", b.model_zone[i].c_str(), b.model_peak[i]),
                    io::printf_text("%s (%.3g)", f.model_zone[i].c_str(), f.model_peak[i])});
    s += grid({"axis", "measured zone", "board model zone (peak)", "model with the elements found"}, zr, "zone-change-table");
    std::vector<std::vector<std::string>> cr;
    for (const auto& c : a.residual.ranking)
      cr.push_back({c.name, num("%.1f", c.delta_bic), c.kept ? "kept" : c.decided ? "rejected" : "not decided",
                    c.reason.empty() ? c.evidence : c.reason});
    s += grid({"candidate", "BIC decrease", "decision", "reason"}, cr, "candidate-table");
    std::string params;
    for (const auto& e : a.residual.effects_added)
      for (const auto& [n, v] : e.parameters) params += (params.empty() ? "" : ", ") + e.name + "." + n + " = " + num("%.4g", v);
    if (!params.empty()) s += "<p class=\"caption\">Fitted: " + escape_xml(params) + "</p>\n";
  } else {
    s += "<p class=\"caption\">" + escape_xml(num("S error against the board model %.2f dB rms", a.s_db_rms)) +
         escape_xml(num(", G error %.2f dB rms (residual loop not run)", a.g_db_rms)) + "</p>\n";
  }
  s += "</section>\n";
  for (size_t i = 0; i < a.measured.axes.size(); ++i) {
    const std::string k = key(a.measured.axes[i].axis);
    s += "<section id=\"axis-" + k + "\"><h2>Axis " + k + "</h2>\n<div class=\"row\">\n";
    for (int f = 0; f < 3; ++f) s += bode(a, i, f, false) + "\n" + bode(a, i, f, true) + "\n";
    s += coherence_plot(a, i) + "\n</div>\n</section>\n";
  }
  if (!a.notes.empty()) {
    s += "<section id=\"notes\"><h2>Notes</h2>\n<ul>\n";
    for (const auto& n : a.notes) s += "<li>" + escape_xml(n) + "</li>\n";
    for (const auto& n : a.residual.notes) s += "<li>" + escape_xml(n) + "</li>\n";
    s += "</ul>\n</section>\n";
  }
  s += "<footer>amb-host sweep analysis</footer>\n</body>\n</html>\n";
  return s;
}

std::string write_sweep_page(const SweepAnalysis& a, const std::string& path) {
  return write_page_file(render_sweep_page(a), path, "sweep report");
}

}  // namespace amb::host::report
