#include "host-tools/core/report/report_builder.hpp"

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/residual/candidate_report.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>

#include "firmware/app/supervisor.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "model/drop/rubbing_states.hpp"
#include "model/drop/sensor_orbit.hpp"

namespace amb::host::report {

namespace {
constexpr double k_two_pi = 6.283185307179586;

/// A duration in ms resolution. Rubbing times are sums of sample periods (0.0035 s comes out
/// of the sum as 0.0034999...) and the wear record keeps them as float (0.0035000001): rounded
/// to 1 us first, the same time prints the same wherever it is quoted.
std::string duration_s(double t_s) { return io::printf_text("%.3f s", std::round(t_s * 1e6) * 1e-6); }
std::string yes_no(bool b) { return b ? "yes" : "no"; }

/// A Unix time as UTC, ISO 8601 ("2026-11-27 16:20:05 UTC").
std::string utc(int64_t unix_s) {
  const std::time_t t = static_cast<std::time_t>(unix_s);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char b[40];
  std::strftime(b, sizeof b, "%Y-%m-%d %H:%M:%S UTC", &tm);
  return b;
}

const char* ab(size_t b) { return b ? "B" : "A"; }
}  // namespace

const std::string& define_figure(ReportData& d, const std::string& name, const std::string& value, const std::string& definition) {
  for (Figure& f : d.figures)
    if (f.name == name) {
      f.value = value;
      f.definition = definition;
      return f.value;
    }
  d.figures.push_back({name, value, definition});
  return d.figures.back().value;
}

ReportData new_report_data(const std::string& title) {
  ReportData d;
  d.title = title;
  d.orbit.unavailable("no event loaded");
  d.rubbing.unavailable("no event loaded");
  d.speed.unavailable("no event loaded");
  d.replay.unavailable("the event was not replayed (amb-host report replays board events unless --no-replay)");
  d.forces.unavailable("contact forces come from the drop model's Phase D record (the Phase C fit, amb-host fit) or a "
                       "simulated drop; neither was given for this event");
  d.load.unavailable("the load over the circumference comes from the Phase D record (this event) and the wear record "
                     "(cumulative); neither was given: pass --wear FILE for the cumulative load");
  d.fit.unavailable("no Phase C fit for this event: `amb-host fit` fits measured-event files; its result is not "
                    "passed to the report");
  d.residual.unavailable("no steady-state residual result was given (amb-host residual on a steady-state record)");
  d.drop_residual.unavailable("no drop-event residual result was given (amb-host residual on a drop event's "
                              "measured-event export)");
  d.wear.unavailable("no wear record given: pass --wear FILE (AMBW, e.g. downloaded with `amb-host fetch`)");
  d.quick_look.unavailable("no board event given");
  return d;
}

void add_event(ReportData& d, const fw::EventRecord& e, const board::BoardConfig& board, const std::string& source) {
  const fw::EventMetadata& m = e.meta;
  const size_t n = e.samples.size();
  const size_t trig = std::min<size_t>(m.trigger_index, n ? n - 1 : 0);
  const double rate = m.rate_hz > 0.0 ? m.rate_hz : board.rate_hz;
  d.subtitle = source;
  auto& f = d.facts.rows;
  f.clear();
  f.emplace_back("board", m.board_name + " (rig " + m.rig_name + ", " + m.board_source + ")");
  f.emplace_back("firmware", m.firmware_version);
  f.emplace_back("event number", std::to_string(m.event_number));
  f.emplace_back("trigger cause", std::string(fw::to_string(m.cause)));
  f.emplace_back("trigger time", io::printf_text("%.4f s (HAL clock)", static_cast<double>(m.trigger_t_ns) * 1e-9));
  if (std::isfinite(m.speed_at_trigger_hz))
    f.emplace_back("speed at trigger", io::printf_text("%.2f Hz", m.speed_at_trigger_hz) + io::printf_text(" (%.0f rpm)", m.speed_at_trigger_hz * 60.0));
  else
    f.emplace_back("speed at trigger", "none: the board's speed estimate was lost");
  if (e.has_analysis) {
    const fw::EventAnalysis& a = e.analysis;
    f.emplace_back("speed source", std::string(fw::to_string(static_cast<fw::SpeedSource>(a.speed_source))) +
                                       (a.speed_lost_at_trigger ? " (LOST at the trigger)"
                                                                : io::printf_text(" (confidence %.2f at the trigger)", a.speed_confidence_at_trigger)));
    QuickLookSummary q;
    q.rows = {{"model", "momentum balance of the rigid rotor on its orbit at the aux-bearing planes (extrapolated from the sensor planes), "
                        "normal force while at the clearance, Hertz impact peak K^0.4 (5/4 m v^2)^0.6 at each new contact; post-trigger window"},
              {"contact constant K", io::printf_text("%.3g N/m^1.5", a.aux_contact_constant_n_per_m1p5)},
              {"load rating C", io::printf_text("%.0f N", a.aux_dynamic_load_rating_n)},
              {"inner-race spin for the life fraction", io::printf_text("%.2f Hz", a.quick_look_spin_hz)}};
    for (size_t b = 0; b < 2; ++b) {
      const fw::AuxQuickLook& x = a.aux[b];
      if (!x.valid) {
        q.bearing[b] = {{"quick-look", "not computed"}};
        continue;
      }
      const std::string peak = define_figure(
          d, std::string("peak contact force ") + ab(b) + ", board quick-look", io::printf_text("%.0f N", x.peak_force_n),
          "computed on the board right after the drop: rigid-rotor momentum balance on the orbit extrapolated to the "
          "aux-bearing plane, plus the Hertz impact peak at each new contact; post-trigger window. Quick and "
          "model-free, it overstates impacts the real (flexible) rotor cushions");
      q.bearing[b] = {{std::string("peak contact force ") + ab(b) + ", board quick-look", peak},
                      {"peak angle", io::printf_text("%.1f deg from +x towards +y", x.peak_angle_deg)},
                      {"life fraction", io::printf_text("%.3g", x.life_fraction)},
                      {"contact time", io::printf_text("%.3f s", x.contact_time_s)}};
    }
    if (a.quick_look_valid)
      d.quick_look.set(std::move(q), source + ": the board's bearing task after the drop (AMBE v2 analysis section)");
    else
      d.quick_look.unavailable("the board computed no quick-look load (no [bearing] table in its board file)");
  } else {
    d.quick_look.unavailable("the event file is AMBE v1: written before the board computed a quick-look load");
  }
  f.emplace_back("window", std::to_string(n) + " samples at " + io::printf_text("%.0f Hz", rate) + io::printf_text(" (%.3f s before, ", trig / rate) +
                               io::printf_text("%.3f s after the trigger)", (static_cast<double>(n - trig)) / rate));
  f.emplace_back("lost samples (seq gaps)", std::to_string(m.seq_gaps));
  if (e.has_diagnosis) {
    f.emplace_back("Phase B", std::string(fw::diag::to_string(e.diagnosis.type)) + io::printf_text(" (confidence %.2f)", e.diagnosis.confidence));
    if (!e.diagnosis.summary.empty()) f.emplace_back("Phase B summary", e.diagnosis.summary);
  }
  if (n == 0) return;
  auto t_of = [&](size_t i) { return (static_cast<double>(i) - static_cast<double>(trig)) / rate; };

  {
    std::vector<std::array<double, 4>> r_m;
    r_m.reserve(n);
    for (const fw::LoopSample& s : e.samples)
      r_m.push_back({s.displacement_m[0], s.displacement_m[1], s.displacement_m[2], s.displacement_m[3]});
    add_orbits(d, board, r_m, trig, rate, m.speed_at_trigger_hz < 0.0 ? -1.0 : 1.0, source);
  }

  SpeedTrace sp;
  for (size_t i = 0; i < n; ++i) {
    sp.t_s.push_back(t_of(i));
    sp.speed_hz.push_back(e.samples[i].speed_hz);
    sp.speed_command_hz.push_back(e.samples[i].speed_command_hz);
    const double tach = e.samples[i].tach_hz;
    sp.plant_speed_hz.push_back(tach >= 0.0 ? tach : NAN);
    sp.not_tracked.push_back(fw::speed_lost(e.samples[i]) ? 1 : 0);
  }
  if (d.cause_chain.empty()) {
    d.cause_chain.push_back("Phase A trigger: " + std::string(fw::to_string(m.cause)));
    if (e.has_diagnosis) d.cause_chain.push_back("Phase B: " + std::string(fw::diag::to_string(e.diagnosis.type)));
  }
  d.speed.set(std::move(sp), source + ": the firmware's speed estimate, drive command and the rig's tachometer per "
                                      "sample; shaded: the board had no valid speed (\"not tracked\")");
}

void add_orbits(ReportData& d, const board::BoardConfig& board, const std::vector<std::array<double, 4>>& r_m, size_t trig,
                double rate_hz, double spin_sign, const std::string& source) {
  const size_t n = r_m.size();
  if (n == 0) return;
  trig = std::min(trig, n - 1);
  const double rate = rate_hz;
  auto t_of = [&](size_t i) { return (static_cast<double>(i) - static_cast<double>(trig)) / rate; };

  // Orbits at both planes through the sensor view (model/drop/sensor_orbit).
  const model::drop::SensorOrbit view(board.plant);
  std::vector<OrbitPlane> planes(2);
  for (int b = 0; b < 2; ++b) {
    OrbitPlane& p = planes[static_cast<size_t>(b)];
    p.name = std::string("bearing ") + (b ? "B" : "A");
    p.clearance_m = board.plant.aux[static_cast<size_t>(b)].clearance_m;
    for (size_t i = 0; i < n; ++i) {
      const std::array<double, 4>& r = r_m[i];
      const auto xy = view.at_sensor_plane(r, b);
      const auto aux = view.at_aux_plane(r, b);
      p.t_s.push_back(t_of(i));
      p.sensor_x_m.push_back(xy[0]);
      p.sensor_y_m.push_back(xy[1]);
      p.aux_x_m.push_back(aux[0] - board.plant.aux[static_cast<size_t>(b)].centre_offset_x_m);
      p.aux_y_m.push_back(aux[1] - board.plant.aux[static_cast<size_t>(b)].centre_offset_y_m);
    }
  }

  // Rubbing states from the measured orbit at the aux planes, from the trigger on.
  std::vector<RubbingTrace> rub;
  const model::drop::RubbingOptions ro;
  for (size_t b = 0; b < 2; ++b) {
    const auto r = model::drop::classify_rubbing(planes[b].aux_x_m, planes[b].aux_y_m, 1.0 / rate, planes[b].clearance_m,
                                                 spin_sign, static_cast<int>(trig), ro);
    RubbingTrace t;
    t.name = planes[b].name;
    for (size_t i = trig; i < n && i < r.angle_rad.size(); ++i) {
      t.t_s.push_back(t_of(i));
      t.angle_deg.push_back(r.angle_rad[i] * 180.0 / 3.141592653589793);
      t.slope_hz.push_back(i < r.slope_rad_s.size() ? r.slope_rad_s[i] / k_two_pi : NAN);
      t.state.push_back(i < r.state.size() ? static_cast<int>(r.state[i]) : 0);
    }
    t.durations_s = {r.durations.swing_s, r.durations.forward_s, r.durations.backward_s};
    const double window_s = static_cast<double>(n - trig) / rate;
    const char* state_names[3] = {"swinging", "forward rub", "backward rub"};
    for (size_t k = 0; k < 3; ++k) {
      const std::string name = std::string(state_names[k]) + " " + ab(b) + ", measured orbit (post-trigger window)";
      t.rows.emplace_back(name, define_figure(d, name, duration_s(t.durations_s[k]),
                                              "time in this state over the whole post-trigger window (" +
                                                  io::printf_text("%.3f s", window_s) +
                                                  "), classified from the measured orbit at the aux-bearing plane"));
    }
    rub.push_back(std::move(t));
  }

  for (size_t b = 0; b < 2; ++b) {
    double r_max = 0.0;
    for (size_t i = trig; i < planes[b].aux_x_m.size(); ++i) r_max = std::max(r_max, std::hypot(planes[b].aux_x_m[i], planes[b].aux_y_m[i]));
    define_figure(d, std::string("largest orbit radius ") + ab(b) + " at the aux-bearing plane, rigid extrapolation",
                  io::printf_text("%.0f \u00b5m", r_max * 1e6) + io::printf_text(" (clearance %.0f \u00b5m)", planes[b].clearance_m * 1e6),
                  "not measured: extrapolated from the two sensor planes as if the rotor were rigid, after the trigger. "
                  "The rotor bends in the drop, so the extrapolation can pass the clearance circle the journal cannot; "
                  "its error is given below where the run is simulated (rigid-extrapolation error), and unknown otherwise");
  }
  d.orbit.set(std::move(planes), source + ": sensors [A1, A2, B1, B2] through the sensor view (aux plane: rigid-rotor extrapolation)");
  d.rubbing.set(std::move(rub), source + ": measured orbit at the aux planes, model/drop/rubbing_states (contact at " +
                                    io::printf_text("%.2f", ro.contact_radius_fraction) + " x clearance)");
}

void add_replay(ReportData& d, const replay::ReplayResult& r) {
  ReplayVerdict v;
  const bool outputs_ok = r.mode == "not_reproducible" || r.comparison.bit_exact;
  v.reproduced = outputs_ok && r.trigger.reproduced && r.diagnosis.type_reproduced;
  const std::string compared = std::to_string(r.comparison.compared_samples) + " samples" +
                               (r.comparison.compare_from == replay::k_no_index
                                    ? std::string()
                                    : " from sample " + std::to_string(r.comparison.compare_from));
  const std::string trigger = "recorded sample " + std::to_string(r.trigger.recorded_index) + " (" + r.trigger.recorded_cause +
                              "), replayed " +
                              (r.trigger.replayed_frozen
                                   ? std::to_string(r.trigger.replayed_index) + " (" + r.trigger.replayed_cause + ")"
                                   : std::string("none"));
  const std::string phase_b = std::string(fw::diag::to_string(r.diagnosis.recorded.type)) + " -> " +
                              fw::diag::to_string(r.diagnosis.replayed.type) + (r.diagnosis.bit_exact ? " (bit-exact)" : "");
  // Built as one list: GCC 12 warns falsely (-Warray-bounds) on emplace_back into an empty vector here.
  v.rows = {{"mode", r.mode},
            {"why", r.compare_from_reason},
            {"compared bit for bit", compared},
            {"mismatched samples", std::to_string(r.comparison.mismatched_samples)},
            {"warm-up", std::to_string(r.warm_up.steps) + " periods, " + r.warm_up.note},
            {"trigger", trigger},
            {"Phase B", phase_b}};
  if (!r.comparison.differences.empty()) {
    const auto& x = r.comparison.differences.front();
    v.rows.emplace_back("first difference", "sample " + std::to_string(x.index) + io::printf_text(" (%+.4f s), ", x.t_from_trigger_s) + x.channel +
                                                io::printf_text(": %.9g", x.recorded) + io::printf_text(" -> %.9g", x.replayed));
  }
  d.replay.set(std::move(v), "amb-host replay: fresh supervisor on the replay HAL backend");
}

void add_drop_trace(ReportData& d, const model::drop::DropTrace& t, const std::string& what) {
  ForceTrace f;
  for (const model::drop::DropSample& s : t.samples) {
    f.t_s.push_back(s.t_s);
    for (size_t b = 0; b < 2; ++b) {
      f.normal_n[b].push_back(s.normal_n[b]);
      f.friction_n[b].push_back(s.friction_n[b]);
    }
  }
  d.forces.set(std::move(f), what + ": Phase D record (mean contact forces per sample)");
  if (!t.contact_steps.empty()) {
    const auto loads = wear::event_load(t.contact_steps);
    LoadMap m = d.load.data.value_or(LoadMap{});
    for (size_t b = 0; b < 2; ++b) m.event_n[b].assign(loads[b].load_n.begin(), loads[b].load_n.end());
    const std::string src = what + ": Phase E load map of the contact steps (host-tools/core/wear/load_map)";
    d.load.set(std::move(m), d.load.source.empty() ? src : d.load.source + "; " + src);
  }
}

void add_fit(ReportData& d, const fit::DropFitResult& r, const std::string& source) {
  FitConvergence c;
  c.cost_history = r.cost_history;
  c.friction_coefficient = r.friction_coefficient;
  c.converged = r.converged;
  c.evaluations = r.evaluations;
  c.wall_s = r.wall_s;
  c.stop_reason = r.stop_reason;
  c.figures.emplace_back("restitution", r.restitution);
  c.figures.emplace_back("friction uncertainty", r.friction_uncertainty);
  c.figures.emplace_back("bound active (1 = yes)", r.bound_active ? 1.0 : 0.0);
  for (size_t b = 0; b < 2; ++b) {
    const std::string k = b ? " B" : " A";
    // Whirl per aux bearing (measured orbit): the direction is in the label, the value is its
    // mean whirl frequency (0 for none / bouncing without a rub).
    c.figures.emplace_back("whirl Hz, " + r.whirl[b].direction + k, r.whirl[b].frequency_hz);
    // The fit compares a shorter window than the event's: its rubbing times are over that
    // window, for the model and for the measurement alike (so they can be compared).
    const double window_s = r.trace.samples.empty() ? 0.0 : r.trace.samples.back().t_s - r.trace.samples.front().t_s;
    const char* state_names[3] = {"swinging", "forward rub", "backward rub"};
    const std::array<double, 3> fitted{r.rubbing[b].swing_s, r.rubbing[b].forward_s, r.rubbing[b].backward_s};
    const std::array<double, 3> measured{r.measured_rubbing[b].swing_s, r.measured_rubbing[b].forward_s,
                                         r.measured_rubbing[b].backward_s};
    for (size_t s = 0; s < 3; ++s) {
      const std::string fit_name = std::string(state_names[s]) + " " + ab(b) + ", fitted drop model (fit window)";
      const std::string meas_name = std::string(state_names[s]) + " " + ab(b) + ", measured orbit (fit window)";
      const std::string why = "over the fit window only (the first " + io::printf_text("%.3f s", window_s) +
                              " after the trigger, amb-host fit --window), not the whole post-trigger window";
      c.rows.emplace_back(fit_name, define_figure(d, fit_name, duration_s(fitted[s]), "time in this state in the fitted model, " + why));
      c.rows.emplace_back(meas_name, define_figure(d, meas_name, duration_s(measured[s]), "time in this state in the measurement, " + why));
    }
  }
  d.fit.set(std::move(c), source);
  if (!r.trace.samples.empty()) add_drop_trace(d, r.trace, "fitted drop model");
}

void add_wear_record(ReportData& d, const fw::WearRecord& w, const std::string& source) {
  WearSummary s;
  s.rows = {{"board", w.board_name},
            {"sequence", std::to_string(w.sequence)},
            {"events accounted", std::to_string(w.event_count)},
            {"life model", w.life_model},
            {"last friction coefficient", io::printf_text("%.4f", w.last_friction_coefficient)},
            {"updated", utc(w.updated_unix_s)}};
  LoadMap m = d.load.data.value_or(LoadMap{});
  for (size_t b = 0; b < 2; ++b) {
    const fw::AuxBearingWear& x = w.bearing[b];
    // Named by bearing and by what they sum (every event of the record, each over its fit
    // window), apart from one event's measured or fitted times.
    const std::string all = std::string(" ") + ab(b) + ", wear record (all events)";
    s.bearing[b] = {{"swinging" + all, duration_s(x.swing_s)},
                    {"forward rub" + all, duration_s(x.forward_rub_s)},
                    {"backward rub" + all, duration_s(x.backward_rub_s)},
                    {"friction energy", io::printf_text("%.2f J", x.friction_energy_j)},
                    {std::string("peak contact force ") + ab(b) + ", fitted drop model (wear record)",
                     define_figure(d, std::string("peak contact force ") + ab(b) + ", fitted drop model (wear record)",
                                   io::printf_text("%.0f N", x.peak_force_n),
                                   "largest step-mean normal contact force of the fitted drop model (Phase C/D, the host's "
                                   "fit) over the events in the wear record; it is the estimate of record for the wear, "
                                   "and differs from the quick-look by the model (flexible rotor, fitted contact) and by "
                                   "the averaging over each integration step")},
                    {"life used", io::printf_text("%.3f %%", 100.0 * x.life_used_fraction)}};
    m.cumulative_n[b].assign(x.cumulative_load_n.begin(), x.cumulative_load_n.end());
    if (m.event_n[b].empty()) {
      bool any = false;
      for (float v : x.event_load_n) any = any || v != 0.0f;
      if (any) m.event_n[b].assign(x.event_load_n.begin(), x.event_load_n.end());
    }
  }
  d.wear.set(std::move(s), source);
  // The host's fitted wear record, once written back, supersedes the board's quick-look.
  if (d.quick_look.available())
    d.quick_look.data->superseded_by = "the fitted wear record (AMBW sequence " + std::to_string(w.sequence) + ", " + source + ")";
  const std::string src = source + ": wear record (AMBW) cumulative load";
  d.load.set(std::move(m), d.load.source.empty() ? src : d.load.source + "; " + src);
}

void add_residual(ReportData& d, const residual::SteadyData& data, const residual::ResidualOutcome& o, const std::string& source) {
  static const char* const names[4] = {"sensor A1", "sensor A2", "sensor B1", "sensor B2"};
  std::vector<ResidualSpectra> out;
  std::string added;
  for (const auto& e : o.effects_added) added += (added.empty() ? "+ " : " + ") + e.name;
  for (size_t c = 0; c < 4; ++c) {
    ResidualSpectra r;
    r.channel = names[c];
    r.unit = "m\u00b2/Hz";
    std::vector<double> before, after;
    for (size_t k = 0; k < data.bands.size(); ++k) {
      r.f_hz.push_back(data.bands[k].f_hz);
      r.measured.push_back(data.bands[k].psd[c]);
      before.push_back(k < o.before.psd_pred.size() ? o.before.psd_pred[k][c] : NAN);
      after.push_back(k < o.after.psd_pred.size() ? o.after.psd_pred[k][c] : NAN);
    }
    r.model_steps.emplace_back("base model", std::move(before));
    r.model_steps.emplace_back(added.empty() ? "after the loop (nothing added)" : "model " + added, std::move(after));
    // The loop's error figures are over all four sensors together: shown once (under the
    // first sensor) and in the Figures table, not repeated as if they were per sensor.
    if (c == 0) {
      const std::string all = " (all four sensors)";
      r.figures = {{"verdict", o.verdict},
                   {"residual spectral error before" + all,
                    define_figure(d, "residual spectral error before" + all, io::printf_text("%.2f dB", o.before.error.spectral),
                                  "the residual loop's spectral error of the base model against the steady record, over "
                                  "the four sensors together")},
                   {"residual spectral error after" + all,
                    define_figure(d, "residual spectral error after" + all, io::printf_text("%.2f dB", o.after.error.spectral),
                                  "the same after the effects the loop added (" + (added.empty() ? std::string("none") : added) +
                                      "); equal to 'before' when an added effect changes the spectra little")},
                   {"rms error before / after" + all, io::printf_text("%.3f", o.before.error.rms) + io::printf_text(" / %.3f", o.after.error.rms)}};
    }
    out.push_back(std::move(r));
  }
  d.residual.set(std::move(out), source + " (the loop reports the model before and after all added effects; "
                                          "intermediate steps are not kept by run_residual_loop)");
}

void add_drop_residual(ReportData& d, const residual::DropResidualOutcome& o, const std::string& source) {
  DropResidualSummary r;
  auto figs = [](const residual::ErrorFigures& e) {
    return io::printf_text("rms %.4f, ", e.rms) + io::printf_text("spectral %.2f dB, ", e.spectral) + io::printf_text("pearson %.3f, ", e.pearson) +
           io::printf_text("statics %.4f", e.statics);
  };
  r.rows.emplace_back("verdict", o.verdict);
  for (const auto& e : o.effects_added) {
    std::string p;
    for (const auto& [k, v] : e.parameters) p += (p.empty() ? "" : ", ") + k + io::printf_text(" = %.4g", v);
    r.rows.emplace_back("added " + e.name, p);
    r.rows.emplace_back("evidence (" + e.name + ")", e.evidence);
  }
  r.rows.emplace_back("event error before", figs(o.before));
  r.rows.emplace_back("event error after", figs(o.after));
  if (o.levitated_analysed) {
    r.rows.emplace_back("levitated part before", figs(o.levitated.before.error));
    r.rows.emplace_back("levitated part after", figs(o.levitated.after.error));
  } else {
    r.rows.emplace_back("levitated part", o.levitated_note);
  }
  r.rows.emplace_back("drop part before", figs(o.drop_before.error) + io::printf_text(", friction %.3f", o.drop_before.friction_coefficient));
  r.rows.emplace_back("drop part after", figs(o.drop_after.error) + io::printf_text(", friction %.3f", o.drop_after.friction_coefficient));
  for (const auto& n : o.drop_notes) r.rows.emplace_back("drop part", n);
  // Every candidate's decision under the engine's one criterion (evidence, value, threshold, reason).
  for (const auto& c : o.drop_ranking) r.rows.emplace_back("candidate (drop part)", residual::candidate_text(c));
  for (size_t b = 0; b < 2; ++b) {
    const auto& m = o.drop_before.measured_circle[b];
    const auto& s = o.drop_before.simulated_circle[b];
    const auto& c = o.drop_before.model_centre_m[b];
    auto um = [](const std::array<double, 2>& v) { return io::printf_text("%+.1f / ", v[0] * 1e6) + io::printf_text("%+.1f um", v[1] * 1e6); };
    r.bearing[b] = {{"model centre (board)", um(c)},
                    {"contact circle, measured", m.valid ? um(m.centre_m) + io::printf_text(" (sigma %.1f um)", m.sigma_m * 1e6) : "too few contact points"},
                    {"contact circle, fitted model", s.valid ? um(s.centre_m) : "too few contact points"},
                    {"effective radius, measured", m.valid ? io::printf_text("%.1f um", m.radius_m * 1e6) : "-"},
                    {"contact points", std::to_string(m.points)}};
  }
  d.drop_residual.set(std::move(r), source);
}

void add_scenario_trace(ReportData& d, const DropScenarioSummary& s) {
  const ScenarioTrace& t = s.trace;
  ForceTrace f;
  SpeedTrace sp;
  for (size_t i = 0; i < t.t_s.size(); ++i) {
    if (t.t_s[i] < s.cut_time_s - 0.05) continue;
    f.t_s.push_back(t.t_s[i] - s.cut_time_s);
    for (size_t b = 0; b < 2; ++b) f.normal_n[b].push_back(i < t.contact_force_n.size() ? t.contact_force_n[i][b] : NAN);
  }
  d.forces.set(std::move(f), "SIL drop scenario (simulated plant truth, time from the AMB cut)");
  // The aux-plane orbit of the plant (truth) beside the rigid extrapolation of the event:
  // the extrapolation's error, measured where the truth is known.
  if (d.orbit.available()) {
    const double t_trigger = s.cut_time_s + 1e-3 * s.trigger_delay_ms;
    for (size_t b = 0; b < d.orbit.data->size() && b < 2; ++b) {
      OrbitPlane& p = (*d.orbit.data)[b];
      if (p.t_s.size() < 2) continue;
      const double dt = p.t_s[1] - p.t_s[0];
      double err_max = 0.0, truth_max = 0.0;
      for (size_t i = 0; i < t.t_s.size() && i < t.aux_x_m.size(); ++i) {
        const double rel = t.t_s[i] - t_trigger;
        if (rel < 0.0 || rel > p.t_s.back()) continue;
        const double x = t.aux_x_m[i][b], y = t.aux_y_m[i][b];
        p.truth_x_m.push_back(x);
        p.truth_y_m.push_back(y);
        truth_max = std::max(truth_max, std::hypot(x, y));
        const long k = std::lround((rel - p.t_s.front()) / dt);
        if (k >= 0 && static_cast<size_t>(k) < p.aux_x_m.size())
          err_max = std::max(err_max, std::hypot(p.aux_x_m[static_cast<size_t>(k)] - x, p.aux_y_m[static_cast<size_t>(k)] - y));
      }
      if (p.truth_x_m.empty()) continue;
      define_figure(d, std::string("largest orbit radius ") + ab(b) + " at the aux-bearing plane, simulated plant (SIL truth)",
                    io::printf_text("%.0f \u00b5m", truth_max * 1e6),
                    "the plant's rotor centre at the aux-bearing plane after the trigger (flexible rotor; the journal "
                    "stops at the clearance plus the contact's penetration)");
      define_figure(d, std::string("rigid-extrapolation error ") + ab(b) + " at the aux-bearing plane",
                    io::printf_text("%.0f \u00b5m", err_max * 1e6),
                    "largest distance, after the trigger, between the rigid-rotor extrapolation of the recorded sensors "
                    "and the plant's rotor centre at the aux-bearing plane (the error of the dashed orbit)");
    }
  }
  if (!d.speed.available()) {
    for (size_t i = 0; i < t.t_s.size() && i < t.speed_hz.size(); ++i) {
      sp.t_s.push_back(t.t_s[i] - s.cut_time_s);
      sp.speed_hz.push_back(t.speed_hz[i]);
    }
    d.speed.set(std::move(sp), "SIL drop scenario (simulated rotor speed, time from the AMB cut)");
  }
  const std::string peak_name = "peak contact force, simulated plant (SIL truth)";
  define_figure(d, peak_name, io::printf_text("%.0f N", s.max_contact_force_n),
                "largest instantaneous contact force of either aux bearing in the simulated plant (the scenario's ground "
                "truth, at the plant's integration sub-steps; no rig has it). Higher than the step-mean and quick-look "
                "figures: impacts last less than one loop period");
  // The cause chain: what was injected, what the board saw first, what latched, where it ended.
  d.cause_chain = {"all AMB channels cut in the plant (injected; the firmware is not told)",
                   "Phase A trigger: " + s.trigger_cause + io::printf_text(" (%.1f ms after the cut)", s.trigger_delay_ms),
                   "fault latched: " + s.fault_reason + io::printf_text(" (%.1f ms after the cut)", s.detection_delay_ms),
                   "safe state: " + s.final_state};
  d.notes.push_back("scenario: " + s.board + ", levitated " + yes_no(s.levitated) + "; the cause chain and the peak contact "
                    "forces (with their definitions) are in the Figures section");
}

}  // namespace amb::host::report
