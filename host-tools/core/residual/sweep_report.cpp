#include "host-tools/core/residual/sweep_report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "host-tools/core/report/frf_overlay.hpp"

namespace amb::host::residual {
namespace {

nlohmann::json errors(const FrfErrors& e) {
  return {{"spectral", e.spectral_db}, {"pearson", e.pearson}, {"rms", e.rms_ln}, {"bins", e.bins}};
}

nlohmann::json modes(const std::vector<ModeMatch>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& m : v)
    a.push_back({{"measured_hz", m.measured_hz}, {"model_hz", std::isfinite(m.model_hz) ? nlohmann::json(m.model_hz) : nlohmann::json(nullptr)},
                 {"error_pct", std::isfinite(m.error_pct) ? nlohmann::json(m.error_pct) : nlohmann::json(nullptr)}, {"mac", m.mac},
                 {"prominence", m.prominence},
                 {"modal_fit", {{"measured_hz", std::isfinite(m.ema_measured_hz) ? nlohmann::json(m.ema_measured_hz) : nlohmann::json(nullptr)},
                                {"model_hz", std::isfinite(m.ema_model_hz) ? nlohmann::json(m.ema_model_hz) : nlohmann::json(nullptr)},
                                {"measured_damping_ratio", m.ema_measured_zeta}, {"model_damping_ratio", m.ema_model_zeta},
                                {"error_pct", std::isfinite(m.ema_error_pct) ? nlohmann::json(m.ema_error_pct) : nlohmann::json(nullptr)},
                                {"mac", m.ema_mac}}}});
  return a;
}

}  // namespace

nlohmann::json sweep_update_json(const SweepOutcome& o) {
  nlohmann::json j;
  nlohmann::json ps = nlohmann::json::array();
  for (size_t i = 0; i < o.parameters.size(); ++i) {
    const auto& p = o.parameters[i];
    ps.push_back({{"name", p.name}, {"unit", p.unit}, {"meaning", p.meaning}, {"nominal", p.nominal}, {"lower", p.lower},
                  {"upper", p.upper}, {"value", p.value}, {"free", p.free}, {"at_bound", o.parameter_at_bound[i]}});
  }
  j["parameters"] = ps;
  const auto& id = o.identifiability;
  j["identifiability"] = {{"free_parameters", id.names}, {"singular_values", id.singular_values}, {"rank", id.rank},
                          {"condition", id.condition}, {"std_normalised", id.std_normalised}, {"correlation", id.correlation},
                          {"notes", id.notes}};
  j["modes_before"] = modes(o.modes_before);
  j["modes_after"] = modes(o.modes_after);
  nlohmann::json v = nlohmann::json::array();
  for (const auto& r : o.validation)
    v.push_back({{"fit_channels", r.fit_channels}, {"check_channels", r.check_channels}, {"fit", errors(r.fit)},
                 {"check", errors(r.check)}, {"check_board_model", errors(r.check_nominal)}});
  j["validation"] = v;
  nlohmann::json nl = nlohmann::json::array();
  for (const auto& s : o.nonlinear) nl.push_back({{"t0_s", s.t0_s}, {"t1_s", s.t1_s}, {"reason", s.reason}});
  j["nonlinear_spans"] = nl;
  j["segments"] = o.frf.segments;
  j["compared_channel_bins"] = o.after.data_points / 2;
  j["current_channel"] = {{"measured_per_control_ampere", o.current_channel}, {"evidence", o.channel_evidence}};
  j["error_updated"] = {{"spectral", o.updated.error.spectral}, {"pearson", o.updated.error.pearson}, {"rms", o.updated.error.rms},
                        {"bic", o.updated.bic}};
  if (o.current_loop.done)
    j["current_per_voltage"] = {{"injection_gain_a_per_v", o.current_loop.gain}, {"model", errors(o.current_loop.error)},
                                {"board_model", errors(o.current_loop.error_board)}};
  return j;
}

namespace {

void write_atomically(const std::string& svg, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot write the FRF overlay to '" + path + "'");
    out << svg;
    if (!out) throw std::runtime_error("cannot write the FRF overlay to '" + path + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot write the FRF overlay to '" + path + "': " + ec.message());
}

std::string figure(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", x);
  return b;
}

}  // namespace

void write_sweep_validation_svg(const SweepOutcome& o, const std::string& path) {
  report::FrfOverlay f;
  f.title = "Held-back accelerometers: measured vs the model fitted on the other half (only the position of a held-back channel is fitted)";
  f.f_hz = o.data.f_hz;
  f.before_label = "board model";
  f.after_label = "fitted on the other half";
  for (const auto& v : o.validation)
    for (size_t c : v.check_channels) {
      f.measured.push_back(o.data.h[c]);
      std::vector<bool> used;
      for (double w : o.data.w[c]) used.push_back(w > 0.0);
      f.compared.push_back(used);
      f.before.push_back(o.before.h_model[c]);
      f.after.push_back(v.h_model[c]);
      std::string fitted;
      for (size_t k : v.fit_channels) fitted += (fitted.empty() ? "" : ",") + std::to_string(k + 1);
      f.channel_names.push_back("accelerometer " + std::to_string(c + 1) + " held back (fitted on " + fitted + "): " +
                                figure(v.check.spectral_db) + " dB, Pearson " + figure(v.check.pearson) + " over the held-back half");
    }
  write_atomically(report::render_frf_overlay_svg(f), path);
}

void write_sweep_current_loop_svg(const SweepOutcome& o, const std::string& path) {
  if (!o.current_loop.done) throw std::runtime_error("no current-per-voltage check in this outcome (no command channel)");
  report::FrfOverlay f;
  const auto& c = o.current_loop;
  f.title = "Excited bearing's current per sweep voltage: measured vs predicted (not fitted; injection gain only)";
  f.f_hz = c.f_hz;
  f.unit = "A/V";
  f.before_label = "";
  f.after_label = "updated model, " + figure(c.error.spectral_db) + " dB, Pearson " + figure(c.error.pearson);
  f.measured = {c.measured};
  f.compared = {c.compared};
  f.after = {c.model};
  f.channel_names = {"I/V"};
  write_atomically(report::render_frf_overlay_svg(f), path);
}

void write_sweep_overlay_svg(const SweepOutcome& o, const std::string& path) {
  report::FrfOverlay f;
  f.title = "Measured vs modelled FRF (acceleration per control current): before " +
            std::to_string(o.before.error.spectral).substr(0, 5) + " dB, after " + std::to_string(o.after.error.spectral).substr(0, 5) +
            " dB rms over the compared bins";
  f.f_hz = o.data.f_hz;
  f.measured = o.data.h;
  for (size_t c = 0; c < o.data.h.size(); ++c) {
    std::vector<bool> used;
    for (double w : o.data.w[c]) used.push_back(w > 0.0);
    f.compared.push_back(used);
    char buf[96];
    std::snprintf(buf, sizeof buf, "accelerometer %zu (fitted at %.0f mm)", c + 1,
                  c < o.after.accel_axial_m.size() ? o.after.accel_axial_m[c] * 1e3 : 0.0);
    f.channel_names.push_back(buf);
  }
  f.before = o.before.h_model;
  f.after = o.after.h_model;
  write_atomically(report::render_frf_overlay_svg(f), path);
}

}  // namespace amb::host::residual
