#include "host-tools/core/sweep/sweep_analysis.hpp"

#include <cmath>
#include <stdexcept>

#include "host-tools/core/io/number_text.hpp"

namespace amb::host::sweep {
namespace {

using cd = std::complex<double>;

nlohmann::json cjson(cd z) { return {{"mag", std::abs(z)}, {"phase_deg", std::arg(z) * 180.0 / M_PI}}; }

nlohmann::json fit_json(const SweepFit& f) {
  return {{"misfit", f.misfit},         {"bic", f.bic},
          {"parameters", f.parameters}, {"data_points", f.data_points},
          {"s_db_rms", f.s_db_rms},     {"g_db_rms", f.g_db_rms},
          {"model_peak", f.model_peak}, {"model_peak_hz", f.model_peak_hz},
          {"model_zone", f.model_zone}, {"peak_ratio", f.peak_ratio}};
}

}  // namespace

const char* axis_name(int axis) {
  static const char* n[4] = {"A1", "A2", "B1", "B2"};
  return axis >= 0 && axis < 4 ? n[axis] : "?";
}

SweepAnalysis analyse_sweep(const SweepRecord& r, const board::BoardConfig& b, const SweepAnalysisOptions& o) {
  if (r.axes.empty()) throw std::invalid_argument("sweep record: no axis was swept" + (r.aborted ? " (aborted: " + r.abort_reason + ")" : std::string()));
  if (r.injection != InjectionPoint::controller_output)
    throw std::invalid_argument("sweep record: injection at the sensor is not supported (only the controller output)");
  SweepAnalysis a;
  a.board_name = r.board_name;
  a.rig_name = r.rig_name;
  a.rate_hz = r.rate_hz;
  a.speed_hz = r.speed_hz;
  a.plan = r.plan;
  a.aborted = r.aborted;
  a.abort_reason = r.abort_reason;
  if (std::abs(r.rate_hz / b.rate_hz - 1.0) > 1e-9)
    throw std::invalid_argument(io::printf_text("sweep record: loop rate %.9g Hz differs from board '%s' (%.9g Hz)", r.rate_hz,
                                                b.name.c_str(), b.rate_hz));
  a.measured = estimate_sweep(r, o.estimate);
  std::vector<int> axes;
  for (const auto& ax : r.axes) axes.push_back(ax.axis);
  std::vector<double> f;
  for (const auto& l : a.measured.axes.front().lines) f.push_back(l.f_hz);
  board::BoardConfig bb = b;
  bb.loop_delay_periods = r.loop_delay_periods;  // the delay the board declared when it ran the sweep
  SweepLoopModel m(bb, r.speed_hz, axes, f);
  a.model = m.board();
  SweepResidualOptions ro = o.residual;
  const bool enough_periods = r.plan.recorded_periods >= o.min_residual_periods;
  if (o.run_residual && !enough_periods)
    a.notes.push_back("residual loop not run: " + std::to_string(r.plan.recorded_periods) +
                      " recorded periods are too few for each line's noise level (the loop needs >= " +
                      std::to_string(o.min_residual_periods) + " periods; its false-alarm rate was measured on 6)");
  if (o.run_residual && enough_periods) {
    a.residual = run_sweep_residual(a.measured, m, ro);
    a.residual_done = true;
    a.s_db_rms = a.residual.before.s_db_rms;
    a.g_db_rms = a.residual.before.g_db_rms;
  } else {
    SweepResidualOptions q = ro;
    q.max_effects = 0;
    const auto r0 = run_sweep_residual(a.measured, m, q);
    a.s_db_rms = r0.before.s_db_rms;
    a.g_db_rms = r0.before.g_db_rms;
    a.residual = r0;
  }
  for (size_t i = 0; i < a.measured.axes.size(); ++i) {
    const auto& ax = a.measured.axes[i];
    ZoneRow z;
    z.axis = ax.axis;
    z.axis_name = axis_name(ax.axis);
    z.measured = ax.peak;
    z.model_peak = a.residual.before.model_peak[i];
    z.model_peak_hz = a.residual.before.model_peak_hz[i];
    z.model_zone = a.residual.before.model_zone[i];
    z.peak_error_pct = ax.peak.found ? 100.0 * (ax.peak.peak / z.model_peak - 1.0) : 0.0;
    a.zones.push_back(z);
  }
  a.notes.push_back("band: " + a.measured.band_basis);
  a.notes.push_back("G is the e-referenced estimate (closed loop: sensor noise reaches u through the controller); H1 and H2 of y/u "
                    "are in the lines");
  if (r.aborted) a.notes.push_back("the board aborted the sweep (" + r.abort_reason + "): the axes that completed are analysed");
  return a;
}

nlohmann::json sweep_analysis_json(const SweepAnalysis& a) {
  nlohmann::json j;
  j["board"] = a.board_name;
  j["rig"] = a.rig_name;
  j["rate_hz"] = a.rate_hz;
  j["speed_hz"] = a.speed_hz;
  j["excitation"] = {{"kind", a.plan.kind == ExcitationKind::multisine ? "multisine" : "stepped_sine"},
                     {"lines", a.plan.frequencies_hz.size()},
                     {"f_min_hz", a.plan.frequencies_hz.empty() ? 0.0 : a.plan.frequencies_hz.front()},
                     {"f_max_hz", a.plan.frequencies_hz.empty() ? 0.0 : a.plan.frequencies_hz.back()},
                     {"samples_per_period", a.plan.samples_per_period},
                     {"recorded_periods", a.plan.recorded_periods},
                     {"amplitude_a", a.plan.amplitude_a},
                     {"crest_factor", a.plan.crest_factor}};
  j["aborted"] = a.aborted;
  if (a.aborted) j["abort_reason"] = a.abort_reason;
  j["band"] = a.measured.band_basis;
  auto& z = j["zones"] = nlohmann::json::array();
  for (const auto& r : a.zones)
    z.push_back({{"axis", r.axis_name},
                 {"zone", r.measured.zone},
                 {"statement", r.measured.statement},
                 {"peak", r.measured.peak},
                 {"band", {r.measured.lo, r.measured.hi}},
                 {"frequency_hz", r.measured.frequency_hz},
                 {"model_peak", r.model_peak},
                 {"model_peak_hz", r.model_peak_hz},
                 {"model_zone", r.model_zone},
                 {"peak_error_pct", r.peak_error_pct}});
  j["error_vs_board_model"] = {{"s_db_rms", a.s_db_rms}, {"g_db_rms", a.g_db_rms}};
  if (a.residual_done) {
    auto& rj = j["residual"];
    rj["verdict"] = a.residual.verdict;
    rj["before"] = fit_json(a.residual.before);
    rj["after"] = fit_json(a.residual.after);
    rj["model_update"] = {{"force_scale", a.residual.update.force_scale},
                          {"delta_bic", a.residual.update.delta_bic},
                          {"at_bound", a.residual.update.at_bound},
                          {"kept", a.residual.update.kept}};
    auto& c = rj["candidates"] = nlohmann::json::array();
    for (const auto& s : a.residual.ranking)
      c.push_back({{"name", s.name}, {"delta_bic", s.delta_bic}, {"decided", s.decided}, {"kept", s.kept}, {"reason", s.reason},
                   {"evidence", s.evidence}});
    auto& e = rj["effects_added"] = nlohmann::json::array();
    for (const auto& x : a.residual.effects_added) {
      nlohmann::json p;
      for (const auto& [n, v] : x.parameters) p[n] = v;
      e.push_back({{"name", x.name}, {"delta_bic", x.delta_bic}, {"parameters", p}});
    }
    rj["notes"] = a.residual.notes;
  }
  auto& ax = j["axes"] = nlohmann::json::array();
  for (size_t i = 0; i < a.measured.axes.size(); ++i) {
    nlohmann::json lines = nlohmann::json::array();
    const auto& m = a.measured.axes[i];
    for (size_t l = 0; l < m.lines.size(); ++l) {
      const auto& q = m.lines[l];
      lines.push_back({{"f_hz", q.f_hz},
                       {"s", cjson(q.s.h)},
                       {"s_band", {q.s.mag_lo, q.s.mag_hi}},
                       {"s_coherence", q.s.coherence},
                       {"t", cjson(q.t.h)},
                       {"g", cjson(q.g.h)},
                       {"g_band", {q.g.mag_lo, q.g.mag_hi}},
                       {"g_h1", cjson(q.g.h1)},
                       {"g_h2", cjson(q.g.h2)},
                       {"g_coherence", q.g.coherence},
                       {"model_s", cjson(a.model[i][l].s)},
                       {"model_t", cjson(a.model[i][l].t)},
                       {"model_g", cjson(a.model[i][l].g)}});
    }
    ax.push_back({{"axis", axis_name(m.axis)}, {"min_s_coherence", m.min_coherence_s}, {"lines", lines}});
  }
  j["notes"] = a.notes;
  return j;
}

}  // namespace amb::host::sweep
