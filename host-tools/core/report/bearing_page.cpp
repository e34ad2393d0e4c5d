#include "host-tools/core/report/bearing_page.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/page_file.hpp"
#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::report {
namespace {

namespace hb = amb::host::bearing;
using io::printf_text;

const char* k_css = R"(table.grid{border-collapse:collapse;margin:8px 0}table.grid th,table.grid td{border:1px solid #ccc;padding:3px 8px;text-align:left;vertical-align:top}
table.grid td.n{font-family:monospace;text-align:right}.verdict{font-weight:bold;font-size:18px})";

// One colour per family, the same in the table and the plots.
const char* family_colour(const std::string& name) {
  if (name == "bpfo") return "#d62728";
  if (name == "bpfi") return "#1f77b4";
  if (name == "ball") return "#2ca02c";
  return "#9467bd";  // ftf
}

std::string plot_id(const hb::AnalysisBand& b) { return "bearing-band-" + b.name; }

std::string band_text(const hb::AnalysisBand& b) {
  if (b.sub_bands > 0)
    return printf_text("%.0f-%.0f Hz, %zu bands combined", b.band.low_hz, b.band.high_hz, b.sub_bands);
  return printf_text("%.0f-%.0f Hz, spectral kurtosis %.2f", b.band.low_hz, b.band.high_hz, b.band.kurtosis);
}

// The family's template lines at its best slip, as they were found in its best band: a tick per
// line above the spectrum's highest bin `top`, so the spectrum under it stays visible (NaN breaks
// the polyline); lines above x_max_hz are left out (0: none).
Series markers(const hb::FamilyResult& f, double top, double x_max_hz) {
  Series s{f.name + (f.detected ? " (detected)" : ""), {}, {}, family_colour(f.name), f.detected ? 1.6 : 1.0, !f.detected};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& l : f.lines.lines) {
    if (!(l.hz > 0) || (x_max_hz > 0 && l.hz > x_max_hz)) continue;
    s.x.insert(s.x.end(), {l.hz, l.hz, nan});
    s.y.insert(s.y.end(), {1.03 * top, 1.15 * top, nan});
  }
  return s;
}

// The low end where the cage family lives: up to 4.5 x FTF (its three harmonics and room).
double low_end_hz(const hb::BearingCheckResult& r) { return 4.5 * r.refined.ftf_hz; }

// The band's normalised spectrum up to x_max_hz (0: all of it); `low`: the zoom on the low end.
std::string band_plot(const hb::BearingCheckResult& r, size_t b, bool low) {
  const auto& ns = r.band_spectra[b];
  const double x_max_hz = low ? low_end_hz(r) : 0.0;
  LinePlot p;
  p.id = plot_id(r.bands[b]) + (low ? "-low" : "");
  p.title = low ? r.bands[b].name + ": the cage family's range"
                : r.bands[b].name + ": envelope spectrum over its floor (" + band_text(r.bands[b]) + ")";
  p.x_label = "frequency (Hz)";
  p.y_label = "amplitude / local median (1)";
  p.width_px = low ? 400 : 780;
  p.height_px = 330;
  Series spec{"envelope spectrum", {}, {}, "#000000", 1.0};
  double top = 1.0;
  for (size_t k = 1; k < ns.ratio.size(); ++k) {
    if (x_max_hz > 0 && static_cast<double>(k) * ns.df_hz > x_max_hz) break;
    const bool aside = k < ns.excluded.size() && ns.excluded[k];
    spec.x.push_back(static_cast<double>(k) * ns.df_hz);
    spec.y.push_back(aside ? std::numeric_limits<double>::quiet_NaN() : ns.ratio[k]);
    if (!aside) top = std::max(top, ns.ratio[k]);
  }
  p.series.push_back(spec);
  // Markers of the families whose best band this is (their lines were found here).
  for (const auto& f : r.families) {
    if (f.band_index != b) continue;
    Series m = markers(f, top, x_max_hz);
    if (!m.x.empty()) p.series.push_back(m);
  }
  p.x_range = std::array<double, 2>{0.0, spec.x.empty() ? 1.0 : spec.x.back()};
  p.y_range = std::array<double, 2>{0.0, 1.18 * top};
  return render_line_plot(p);
}

}  // namespace

std::vector<std::string> bearing_plot_ids(const hb::BearingCheckResult& r) {
  std::vector<std::string> ids;
  for (size_t b = 0; b < r.bands.size() && b < r.band_spectra.size(); ++b)
    if (!r.band_spectra[b].ratio.empty()) {
      ids.push_back(plot_id(r.bands[b]));
      ids.push_back(plot_id(r.bands[b]) + "-low");
    }
  return ids;
}

std::string render_bearing_page(const hb::BearingCheckResult& r, const BearingPageInfo& info) {
  const std::string title = "Bearing check " + info.record;
  std::string s = page_head(title, k_css);
  s += "<h1>" + escape_xml(title) + "</h1>\n<p class=\"sub\">" +
       escape_xml(info.bearing + " on " + info.variable + printf_text(", fs %.0f Hz, %.1f rpm nominal", info.fs_hz, info.nominal_rpm)) +
       "</p>\n";
  s += "<section id=\"verdict\"><h2>Verdict</h2>\n<p class=\"verdict\">" + escape_xml(r.verdict) + "</p>\n<p class=\"caption\">" +
       escape_xml(r.reason) + "</p>\n";
  s += "<table class=\"facts\">\n";
  auto fact = [&](const std::string& k, const std::string& v) {
    s += "<tr><th>" + escape_xml(k) + "</th><td>" + escape_xml(v) + "</td></tr>\n";
  };
  fact("speed", r.speed.refined ? printf_text("refined to %.4f Hz from the %s", r.speed.speed_hz, r.speed_source.c_str())
                                : printf_text("not refined: nominal %.4f Hz", r.speed.speed_hz));
  fact("pre-whitening", r.whitening);
  fact("detection threshold", printf_text("log10 P_null < %.2f", r.threshold_log10_p));
  if (r.raw_cage.run)
    fact("raw cage scan", printf_text("%zu raw bands, best %.0f-%.0f Hz, score %.1f against %.1f: %s", r.raw_cage.bands,
                                      r.raw_cage.band.low_hz, r.raw_cage.band.high_hz, r.raw_cage.score,
                                      r.raw_cage.threshold_score, r.raw_cage.detected ? "detected" : "not detected"));
  s += "</table>\n</section>\n";
  s += "<section id=\"families\"><h2>Families</h2>\n<table class=\"grid\">\n<tr><th>family</th><th>predicted Hz</th><th>found "
       "Hz</th><th>score</th><th>threshold</th><th>log10 P_null</th><th>band</th><th>decision</th></tr>\n";
  for (const auto& f : r.families) {
    s += "<tr><td style=\"color:" + std::string(family_colour(f.name)) + "\"><b>" + escape_xml(f.name) + "</b></td><td class=\"n\">" +
         printf_text("%.2f", f.predicted_hz) + "</td><td class=\"n\">" + (f.found_hz ? printf_text("%.2f", *f.found_hz) : "-") +
         "</td><td class=\"n\">" + printf_text("%.1f", f.score) + "</td><td class=\"n\">" + printf_text("%.1f", f.threshold_score) +
         "</td><td class=\"n\">" + printf_text("%.1f", f.log10_p) + "</td><td>" + escape_xml(r.bands[f.band_index].name) +
         "</td><td>" + escape_xml(f.reason) + "</td></tr>\n";
  }
  s += "</table>\n</section>\n";
  s += "<section id=\"spectra\"><h2>Envelope spectra</h2>\n<p class=\"caption\">Each analysis band's envelope spectrum divided "
       "by its running median (under noise a bin exceeds r with probability 2^-r^2), and a zoom on the cage family's "
       "range. Ticks above the curve: a family's template lines where its score found them, drawn in the band where "
       "that family scored best (solid: a detected family, dashed: not). Bins on shaft harmonics of the refined speed are set aside (gaps in the curve).</p>\n";
  for (size_t b = 0; b < r.bands.size(); ++b) {
    if (b < r.band_spectra.size() && !r.band_spectra[b].ratio.empty())
      s += "<div class=\"row\">" + band_plot(r, b, false) + band_plot(r, b, true) + "</div>\n";
    else
      s += "<p class=\"caption\">" + escape_xml(r.bands[b].name) + ": spectrum not available</p>\n";
  }
  s += "</section>\n<footer>amb-host bearing-check (docs/bearing.md)</footer>\n</body>\n</html>\n";
  return s;
}

}  // namespace amb::host::report
