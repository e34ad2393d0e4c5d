#include "host-tools/core/hybrid/hybrid_page.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "host-tools/core/report/svg_plot.hpp"

namespace amb::host::hybrid {
namespace {

namespace rp = amb::host::report;

std::string num(double v, const char* fmt) {
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

// The physics spectra are in the simulation's own units (assumed housing mass): for the plot
// the log spectrum is shifted and the envelope scaled to the hybrid's mean (named in the legend).
std::vector<double> shifted(const std::vector<double>& v, double by) {
  std::vector<double> o(v);
  for (double& x : o) x += by;
  return o;
}
std::vector<double> scaled(const std::vector<double>& v, double by) {
  std::vector<double> o(v);
  for (double& x : o) x *= by;
  return o;
}

rp::LinePlot plot(const HybridPageData& d, bool log_spectrum) {
  const Prediction& p = d.prediction;
  rp::LinePlot pl;
  pl.id = log_spectrum ? "hybrid-log-spectrum" : "hybrid-envelope";
  pl.title = log_spectrum ? "Log spectrum: measured, hybrid with its band, baselines" : "Envelope spectrum: measured, hybrid with its band, baselines";
  pl.x_label = "frequency (Hz)";
  pl.y_label = log_spectrum ? "log10 PSD (log10 g^2/Hz)" : "envelope amplitude (g^2)";
  pl.width_px = 980;
  pl.height_px = 420;
  const auto& x = log_spectrum ? p.psd_hz : p.env_hz;
  const auto& hy = log_spectrum ? p.log_psd_hybrid : p.env_hybrid;
  pl.bands.push_back({"hybrid band", x, log_spectrum ? p.log_psd_hybrid_lo : p.env_hybrid_lo,
                      log_spectrum ? p.log_psd_hybrid_hi : p.env_hybrid_hi, "#e67e22"});
  if (!d.measured_path.empty()) pl.series.push_back({"measured", x, log_spectrum ? d.measured.log_psd : d.measured.env, "#111", 1.6});
  pl.series.push_back({"hybrid", x, hy, "#d35400", 1.8});
  const auto& interp = log_spectrum ? p.log_psd_interp : p.env_interp;
  const auto& near = log_spectrum ? p.log_psd_transport : p.env_transport;
  if (!interp.empty()) pl.series.push_back({"interpolated transport", x, interp, "#2471a3", 1.2, true});
  if (!near.empty()) pl.series.push_back({"nearest transport", x, near, "#5dade2", 1.0, true});
  const auto& data = log_spectrum ? p.log_psd_data_only : p.env_data_only;
  pl.series.push_back({"data only", x, data, "#27ae60", 1.0, true});
  const auto& phys = log_spectrum ? p.log_psd_physics : p.env_physics;
  if (log_spectrum) {
    pl.series.push_back({"physics (shifted to the hybrid's mean)", x, shifted(phys, mean(hy) - mean(phys)), "#8e44ad", 1.0, true});
  } else {
    const double mp = mean(phys);
    pl.series.push_back({"physics (scaled to the hybrid's mean)", x, scaled(phys, mp > 0 ? mean(hy) / mp : 1.0), "#8e44ad", 1.0, true});
  }
  return pl;
}

}  // namespace

std::vector<std::string> hybrid_page_plot_ids() { return {"hybrid-log-spectrum", "hybrid-envelope"}; }

std::string render_hybrid_page(const HybridPageData& d) {
  const Prediction& p = d.prediction;
  std::string o =
      "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>Hybrid model prediction</title><style>"
      "body{font-family:sans-serif;margin:1.5em;max-width:1200px}table{border-collapse:collapse;margin:.5em 0}"
      "td,th{border:1px solid #bbb;padding:2px 8px;font-size:13px}th{background:#eee}td.n{text-align:right}"
      "tr.hybrid td{font-weight:bold}</style></head><body><h1>Physics-informed hybrid model (seed 001)</h1>";
  o += "<p id=\"facts\">state <b>" + std::string(state_name(d.state)) + "</b> at " + num(d.op.speed_rpm, "%g") + " rpm, load " +
       num(d.op.load, "%g") + "; model " + rp::escape_xml(d.model_path) + " trained at";
  for (const auto& t : d.trained_at) o += " " + rp::escape_xml(t);
  o += ". Hybrid: " + rp::escape_xml(p.hybrid_kind == "correction" ? "learned correction of the interpolated transport"
                                     : p.hybrid_kind == "map"      ? "learned map of the 8-DOF physics"
                                                                   : "learned map of the 8-DOF physics (no training record of the state)");
  if (!p.interp_cases.empty()) o += "; transported from " + rp::escape_xml(p.interp_cases);
  o += ".</p>";
  if (d.measured_path.empty()) {
    o += "<p id=\"hybrid-scores-na\">not available: no measured record given (--measured)</p>";
  } else {
    o += "<h2>Against " + rp::escape_xml(d.measured_path) + "</h2>";
    o += "<table id=\"hybrid-scores\"><tr><th>model</th><th>log spectrum Pearson</th><th>log spectrum MSE</th>"
         "<th>envelope Pearson</th><th>envelope MSE</th></tr>";
    for (const auto& s : d.scores) {
      o += "<tr" + std::string(s.model == "hybrid" ? " class=\"hybrid\"" : "") + "><td>" + rp::escape_xml(s.model) + "</td>";
      if (!s.available) {
        o += "<td colspan=\"4\">not available: no training record of the state</td></tr>";
        continue;
      }
      o += "<td class=\"n\">" + num(s.log_pearson, "%.3f") + "</td><td class=\"n\">" + num(s.log_mse, "%.4g") + "</td><td class=\"n\">" +
           num(s.env_pearson, "%.3f") + "</td><td class=\"n\">" + num(s.env_mse, "%.4g") + "</td></tr>";
    }
    o += "</table>";
  }
  o += "<h2>Spectra</h2><p>The band: the ensemble's range widened by the 10-90 % quantiles of the inner cross-validation "
       "residuals (nominal 80 % of the bins).</p>";
  o += rp::render_line_plot(plot(d, true));
  o += rp::render_line_plot(plot(d, false));
  o += "</body></html>\n";
  return o;
}

void write_hybrid_page(const HybridPageData& d, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write '" + path + "'");
    f << render_hybrid_page(d);
    if (!f) throw std::runtime_error("error writing '" + path + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot write '" + path + "': " + ec.message());
}

}  // namespace amb::host::hybrid
