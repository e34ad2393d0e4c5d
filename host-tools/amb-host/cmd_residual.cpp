// amb-host residual EVENT: close the loop with measured data. EVENT is a measured-event
// sidecar (NAME.json, formats/measured-event.md) of a steady-state run, or a current-to-
// response sweep: a directory holding Sweep_Time_Anregung.mat + Sweep_Time_Ausgang.mat
// (the TUM MLPS export; board tum-mlps-rig unless --board says otherwise).
// Logic: host-tools/core/residual/.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/residual/candidate_report.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/engine/elements.hpp"
#include "host-tools/core/residual/journal_residual.hpp"
#include "host-tools/core/residual/learned_correction.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"
#include "host-tools/core/residual/sweep_report.hpp"

namespace {

namespace hr = amb::host::residual;

struct Args {
  std::string event;
  std::string board;
  bool json = false;
  bool contact_law_update = false;
  bool learned_correction = false;  // after the loop: a learned map, reported apart from the named elements
  std::string plot;  // sweep: FRF overlay SVG path
};

nlohmann::json figures(const hr::ErrorFigures& e) {
  return {{"rms", e.rms}, {"spectral", e.spectral}, {"pearson", e.pearson}, {"statics", e.statics}};
}

nlohmann::json added(const std::vector<hr::EffectAdded>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& e : v) {
    nlohmann::json p = nlohmann::json::object();
    for (const auto& [k, x] : e.parameters) p[k] = x;
    a.push_back({{"name", e.name}, {"parameters", p}, {"evidence", e.evidence}, {"delta_bic", e.delta_bic}});
  }
  return a;
}

nlohmann::json ranking(const std::vector<hr::CandidateScore>& v) { return hr::candidates_json(v); }

void print_text(const std::string& verdict, const hr::ErrorFigures& b, const hr::ErrorFigures& a,
                const std::vector<hr::CandidateScore>& rank, const std::vector<hr::EffectAdded>& add,
                const std::vector<std::string>& notes) {
  std::printf("residual structure:\n");
  for (const auto& n : notes) std::printf("  %s\n", n.c_str());
  std::printf("candidates (best first):\n");
  for (const auto& c : rank) std::printf("  %s\n", hr::candidate_text(c).c_str());
  for (const auto& e : add) {
    std::printf("added %s:", e.name.c_str());
    for (const auto& [k, x] : e.parameters) std::printf(" %s=%.4g", k.c_str(), x);
    std::printf("\n");
  }
  std::printf("error before: rms %.4g  spectral %.3g  pearson %.3f\n", b.rms, b.spectral, b.pearson);
  std::printf("error after : rms %.4g  spectral %.3g  pearson %.3f\n", a.rms, a.spectral, a.pearson);
  std::printf("verdict: %s\n", verdict.c_str());
}

nlohmann::json model_update(const hr::ResidualOutcome& o) {
  const auto& u = o.model_update;
  return {{"done", u.done}, {"loop_delay_s", u.loop_delay_s}, {"force_scale", u.force_scale},
          {"force_noise_rms_n", u.force_noise_rms_n}, {"sensor_noise_rms_m", u.noise_rms_m}, {"delta_bic", u.delta_bic},
          {"at_bound", u.at_bound},
          {"error_after_update", figures(o.updated.error)}};
}

nlohmann::json unexplained(const std::vector<hr::UnexplainedItem>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& u : v) {
    nlohmann::json j = {{"part", u.part}, {"kind", u.kind}, {"plane", u.plane == 0 ? "A" : u.plane == 1 ? "B" : "?"}};
    if (u.kind == "band") {
      j["f_hz"] = u.f_hz;
      j["level_db"] = u.level_db;
      if (u.f_hi_hz > 0.0) j["f_hi_hz"] = u.f_hi_hz;
    } else if (u.kind == "order") {
      j.update({{"f_hz", u.f_hz}, {"order", u.order}, {"snr", u.snr}, {"direction", u.direction}, {"amplitude_m", u.amplitude_m}});
    } else {  // contact_compliance: plane = aux bearing
      j.update({{"compliance_m_per_n", u.value}, {"snr", u.snr}, {"radius_change_m", u.amplitude_m}});
    }
    a.push_back(j);
  }
  return a;
}

nlohmann::json drop_errors(const hr::DropErrors& e) {
  nlohmann::json c = nlohmann::json::array();
  for (int k = 0; k < 2; ++k) {
    const auto& m = e.measured_circle[static_cast<size_t>(k)];
    const auto& s = e.simulated_circle[static_cast<size_t>(k)];
    c.push_back({{"bearing", k}, {"valid", m.valid && s.valid}, {"measured_centre_m", m.centre_m},
                 {"simulated_centre_m", s.centre_m}, {"model_centre_m", e.model_centre_m[static_cast<size_t>(k)]},
                 {"sigma_m", m.sigma_m}, {"contact_points", m.points}});
  }
  return {{"error", figures(e.error)}, {"phase_c_cost", e.cost}, {"friction_coefficient", e.friction_coefficient},
          {"contact_circles", c}};
}

// The learned correction, apart from the named elements: JSON (key "learned_correction") and text.
nlohmann::json score_json(const hr::CorrectionScore& c) {
  return {{"unexplained_before_db", c.before_db}, {"unexplained_after_db", c.after_db}, {"noise_floor_db", c.noise_floor_db},
          {"absorbed_fraction", c.absorbed_fraction},
          {"absorbed_fraction_of_excess",
           std::isfinite(c.absorbed_fraction_of_excess) ? nlohmann::json(c.absorbed_fraction_of_excess) : nlohmann::json(nullptr)},
          {"points", c.points}};
}

nlohmann::json correction_json(const hr::LearnedCorrectionSummary& s) {
  nlohmann::json j = {{"done", s.done}, {"note", s.note.empty() ? "learned correction: not a physical explanation, not part of the verdict" : s.note},
                      {"domain", s.domain}};
  if (!s.done) {
    j["skipped"] = s.skipped_why;
    return j;
  }
  j.update({{"trained_on", s.trained_on}, {"scored_on", s.scored_on}, {"noise_floor_source", s.noise_floor_source}});
  j.update(score_json(s.held_out));
  j["training_part"] = score_json(s.training);
  if (s.has_reverse) {
    j["reverse"] = score_json(s.reverse_held_out);
    j["reverse"]["trained_on"] = s.reverse_trained_on;
    j["reverse"]["scored_on"] = s.reverse_scored_on;
  }
  nlohmann::json g = nlohmann::json::array();
  for (const auto& x : s.groups)
    g.push_back({{"group", x.name}, {"lambda", x.lambda}, {"effective_parameters", x.effective_parameters}, {"weights", x.weights},
                 {"held_out", score_json(x.held_out)}});
  j["groups"] = g;
  j["map_size"] = {{"weights", s.weights}, {"effective_parameters", s.effective_parameters}, {"training_points", s.training_points},
                   {"knot_spacing_octaves", s.knot_spacing_octaves}, {"gain_bands", s.gain_bands}};
  return j;
}

void print_correction(const hr::LearnedCorrectionSummary& s) {
  std::printf("learned correction (NOT a physical explanation; not part of the verdict):\n");
  if (!s.done) {
    std::printf("  skipped: %s\n", s.skipped_why.c_str());
    return;
  }
  const auto line = [](const char* what, const hr::CorrectionScore& c) {
    std::printf("  %s: unexplained %.3g dB -> %.3g dB (noise floor %.3g dB), absorbed %.1f %%", what, c.before_db, c.after_db,
                c.noise_floor_db, 100.0 * c.absorbed_fraction);
    if (std::isfinite(c.absorbed_fraction_of_excess)) std::printf(" (%.1f %% of the excess over the floor)", 100.0 * c.absorbed_fraction_of_excess);
    std::printf(", %d points\n", c.points);
  };
  std::printf("  %s\n  trained on %s, scored on %s\n", s.domain.c_str(), s.trained_on.c_str(), s.scored_on.c_str());
  line("held out", s.held_out);
  if (s.has_reverse) line("reverse (parts swapped)", s.reverse_held_out);
  line("training part (optimistic)", s.training);
  for (const auto& g : s.groups)
    std::printf("  %-16s %.3g -> %.3g dB, lambda %.3g, %.1f effective of %d weights\n", g.name.c_str(), g.held_out.before_db,
                g.held_out.after_db, g.lambda, g.effective_parameters, g.weights);
  std::printf("  map: %d weights, %.1f effective parameters, trained on %d points\n", s.weights, s.effective_parameters,
              s.training_points);
}

// The levitated part of a drop event, extracted as run_drop_residual() does (pre-trigger
// history, window = min(2 s, history - 50 ms)), for the learned correction.
hr::LearnedCorrectionSummary drop_levitated_correction(const amb::host::LoadedEvent& rec, const amb::board::BoardConfig& b,
                                                       const hr::DropResidualOutcome& o) {
  hr::LearnedCorrectionSummary s;
  if (!o.levitated_analysed) {
    s.skipped_why = "drop event: the levitated part was not analysed (" + o.levitated_note + ")";
    return s;
  }
  const auto trig = static_cast<size_t>(rec.trigger_index);
  amb::host::LoadedEvent pre = hr::slice_event(rec, 0, trig);
  pre.trigger_index = 0;
  hr::SteadyOptions so;
  so.window_s = std::min(so.window_s, static_cast<double>(trig) / rec.sample_rate_hz - 0.05);
  try {
    const auto d = hr::extract_steady(pre, b, so);
    s = hr::learned_correction_steady(d, o.levitated.after, {}, so);
  } catch (const std::exception& e) {  // the loop read this part already; a stated skip, never the command's failure
    s.skipped_why = std::string("levitated part: ") + e.what();
    return s;
  }
  s.domain = "levitated part: " + s.domain;
  return s;
}

int run_drop(const Args& a, const amb::host::LoadedEvent& rec, const amb::board::BoardConfig& b) {
  std::fprintf(stderr, "drop event: levitated part through the steady loop, drop part through the drop model fit\n");
  hr::DropResidualOptions dro;
  dro.update_contact_law = a.contact_law_update;
  const auto o = hr::run_drop_residual(rec, b, dro);
  std::vector<std::string> notes;
  if (o.levitated_analysed) {
    for (const auto& n : o.levitated.structure.notes) notes.push_back("levitated: " + n);
  } else {
    notes.push_back(o.levitated_note);
  }
  for (const auto& n : o.drop_notes) notes.push_back("drop: " + n);
  std::vector<hr::CandidateScore> rank = o.levitated_analysed ? o.levitated.ranking : std::vector<hr::CandidateScore>{};
  rank.insert(rank.end(), o.drop_ranking.begin(), o.drop_ranking.end());
  if (a.json) {
    nlohmann::json j;
    j["event_kind"] = "drop";
    j["effects_added"] = added(o.effects_added);
    j["error_before"] = figures(o.before);
    j["error_after"] = figures(o.after);
    j["verdict"] = o.verdict;
    j["ranking"] = ranking(rank);
    j["structure"] = notes;
    nlohmann::json seg;
    if (o.levitated_analysed) {
      seg["levitated"] = {{"error_before", figures(o.levitated.before.error)},
                          {"error_after", figures(o.levitated.after.error)},
                          {"verdict", o.levitated.verdict},
                          {"model_update", model_update(o.levitated)}};
    }
    j["unexplained"] = unexplained(o.unexplained);
    nlohmann::json ro = {{"testable", o.drop_runout.testable}, {"applied_from", o.runout_source},
                         {"angle_known_after_trigger_s", o.angle_known_after_trigger_s}};
    if (o.drop_runout.testable) {
      nlohmann::json ph = nlohmann::json::array();
      for (size_t p = 0; p < 2; ++p)
        for (size_t h = 0; h < 2; ++h)
          ph.push_back({{"plane", p == 0 ? "A" : "B"}, {"order", h + 1}, {"amplitude_m", std::abs(o.drop_runout.runout.r_m[p][h])},
                        {"sigma_m", o.drop_runout.sigma_m[p][h]}});
      ro.update({{"phasors", ph}, {"floor_1x_m", o.runout_floor_m}, {"delta_bic", o.drop_runout.delta_bic},
                 {"contact_points", o.drop_runout.points}});
    } else {
      ro["why_not"] = o.drop_runout.why_not;
    }
    nlohmann::json co = {{"testable", o.compliance.testable}};
    if (o.compliance.testable)
      co.update({{"compliance_m_per_n", o.compliance.compliance_m_per_n}, {"sigma_m_per_n", o.compliance.sigma_m_per_n},
                 {"mean_force_n", o.compliance.mean_force_n}});
    seg["drop"] = {{"before", drop_errors(o.drop_before)}, {"after", drop_errors(o.drop_after)}, {"contact_law", o.contact_law},
                   {"runout", ro}, {"contact_compliance", co}};
    j["segments"] = seg;
    if (a.learned_correction) j["learned_correction"] = correction_json(drop_levitated_correction(rec, b, o));
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_text(o.verdict, o.before, o.after, rank, o.effects_added, notes);
    if (a.learned_correction) print_correction(drop_levitated_correction(rec, b, o));
  }
  return 0;
}

int run_steady(const Args& a) {
  const amb::host::LoadedEvent rec = amb::host::load_event(a.event);
  for (const auto& w : rec.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const auto b = a.board.empty() ? amb::host::resolve_rig(rec.rig, std::filesystem::path(rec.source).parent_path().string(), rec.source)
                                 : amb::board::load_board(a.board);
  if (hr::is_drop_event(rec, b)) return run_drop(a, rec, b);
  if (hr::is_journal_event(rec, b)) {  // journal-bearing record (seed 002): journal_bearing_wear
    const auto o = hr::run_journal_residual(rec, b);
    if (a.learned_correction) std::fprintf(stderr, "--learned-correction: not available for journal-bearing records (skipped)\n");
    std::printf("%s\n", a.json ? hr::journal_residual_json(o).c_str() : hr::journal_residual_text(o).c_str());
    return 0;
  }
  const auto d = hr::extract_steady(rec, b);
  const auto o = hr::run_residual_loop(d, b);
  // After the loop has decided: the learned correction reads its final model and changes nothing.
  hr::LearnedCorrectionSummary lc;
  if (a.learned_correction) lc = hr::learned_correction_steady(d, o.after);
  if (a.json) {
    nlohmann::json j;
    j["effects_added"] = added(o.effects_added);
    j["error_before"] = figures(o.before.error);
    j["error_after"] = figures(o.after.error);
    j["verdict"] = o.verdict;
    j["ranking"] = ranking(o.ranking);
    j["structure"] = o.structure.notes;
    j["spin_hz"] = d.spin_hz;
    j["bic_before"] = o.before.bic;
    j["bic_after"] = o.after.bic;
    nlohmann::json fs = nlohmann::json::array();
    for (const auto& l : o.structure.full_spectrum)
      fs.push_back({{"plane", l.plane}, {"order", l.order}, {"forward_measured_m", l.forward_measured_m},
                    {"backward_measured_m", l.backward_measured_m}, {"forward_residual_m", l.forward_residual_m},
                    {"backward_residual_m", l.backward_residual_m}});
    j["full_spectrum"] = fs;
    j["model_update"] = model_update(o);
    j["unexplained"] = unexplained(o.unexplained);
    j["channel_rms_residual"] = o.structure_after.channel_rms_residual;
    j["orbit_residual_max_m"] = o.structure_after.orbit_residual_max_m;
    if (a.learned_correction) j["learned_correction"] = correction_json(lc);
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_text(o.verdict, o.before.error, o.after.error, o.ranking, o.effects_added, o.structure.notes);
    if (a.learned_correction) print_correction(lc);
  }
  return 0;
}

int run_sweep(const Args& a) {
  const auto rec = hr::read_tum_sweep(a.event);  // SI units (Test.Lab stores MKS)
  const auto b = amb::board::load_board(a.board.empty() ? "tum-mlps-rig" : a.board);
  const auto o = hr::run_sweep_residual(rec.current_a, rec.accel_m_s2, rec.fs_hz, b, {}, rec.command_v);
  if (!a.plot.empty()) {
    // PATH.svg: all accelerometers; PATH-validation.svg: the held-back ones; PATH-current.svg: I/V.
    const std::string stem = a.plot.size() > 4 && a.plot.substr(a.plot.size() - 4) == ".svg" ? a.plot.substr(0, a.plot.size() - 4) : a.plot;
    hr::write_sweep_overlay_svg(o, a.plot);
    if (!o.validation.empty()) hr::write_sweep_validation_svg(o, stem + "-validation.svg");
    if (o.current_loop.done) hr::write_sweep_current_loop_svg(o, stem + "-current.svg");
    std::fprintf(stderr, "FRF overlays written to %s (and -validation, -current)\n", a.plot.c_str());
  }
  if (a.json) {
    nlohmann::json j;
    j["effects_added"] = added(o.effects_added);
    j["error_before"] = figures(o.before.error);
    j["error_after"] = figures(o.after.error);
    j["verdict"] = o.verdict;
    j["ranking"] = ranking(o.ranking);
    j["structure"] = o.notes;
    j["accelerometer_axial_m"] = o.after.accel_axial_m;
    j["excited_axis"] = o.after.excited_axis;
    j["gain_scale"] = o.after.gain_scale;
    j["bic_before"] = o.before.bic;
    j["bic_after"] = o.after.bic;
    j["model_updating"] = hr::sweep_update_json(o);
    if (a.learned_correction) j["learned_correction"] = correction_json(hr::learned_correction_sweep(o));
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    print_text(o.verdict, o.before.error, o.after.error, o.ranking, o.effects_added, o.notes);
    if (a.learned_correction) print_correction(hr::learned_correction_sweep(o));
  }
  return 0;
}

const amb::host::Registration reg{
    "residual", "Find the residual between measurement and model, trace it to a missing effect, add it, report",
    [](CLI::App& sub, std::function<int()>& run) {
      auto a = std::make_shared<Args>();
      sub.add_option("EVENT", a->event, "measured-event sidecar (.json) or a sweep directory (TUM .mat pair)")->required();
      sub.add_option("--board", a->board, "board name or file (default: the event's rig; tum-mlps-rig for a sweep)");
      sub.add_flag("--json", a->json, "print the figures as JSON");
      sub.add_flag("--contact-law-update", a->contact_law_update,
                   "drop events: fit the drop model with each contact law (rigid, hertz, linear) and keep the best");
      sub.add_flag("--learned-correction", a->learned_correction,
                   "after the named elements: train a regularised map (ridge) from the final model's spectra to the "
                   "measured ones on one part of the record, score it on the other, and report how much of the "
                   "unexplained error it absorbs (not a physical explanation; the verdict is unchanged)");
      sub.add_option("--plot", a->plot, "sweep only: write the measured vs modelled FRF overlay (SVG) to this file");
      // The element catalogue and the one criterion, in the help (engine/elements.hpp, engine/criterion.hpp).
      std::string footer = "Elements the loop can add (record kinds that test them):\n";
      for (const auto& e : hr::engine::element_catalogue()) {
        std::string kinds;
        for (auto k : e.kinds) kinds += std::string(kinds.empty() ? "" : ", ") + hr::engine::record_kind_name(k);
        footer += "  " + e.name + " (" + kinds + "): " + e.what + "\n";
      }
      footer += "An element is kept when its information-criterion (BIC) decrease on the record's reproducible features "
                "exceeds the threshold (10), its predicted change exceeds 3 noise standard errors, its parameters are "
                "identified, no decision feature rises and one falls by 10 % (docs/residual.md).\n"
                "Example: amb-host residual ../shared/data/synthetic/bath_drop_example_3.json --json";
      sub.footer(footer);
      run = [a]() {
        try {
          if (std::filesystem::is_directory(a->event)) return run_sweep(*a);
          if (!std::filesystem::exists(a->event)) {
            std::fprintf(stderr, "amb-host residual: error: '%s' does not exist\n", a->event.c_str());
            return 1;
          }
          return run_steady(*a);
        } catch (const std::exception& e) {
          std::fprintf(stderr, "amb-host residual: error: %s\n", e.what());
          return 1;
        }
      };
    }};

}  // namespace
