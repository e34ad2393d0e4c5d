#include "host-tools/core/residual/residual_json.hpp"

#include <cmath>

#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/residual/candidate_report.hpp"
#include "host-tools/core/residual/sweep_report.hpp"

namespace amb::host::residual {
namespace {

nlohmann::json model_update_json(const ResidualOutcome& o) {
  const auto& u = o.model_update;
  return {{"done", u.done}, {"loop_delay_s", u.loop_delay_s}, {"force_scale", u.force_scale},
          {"force_noise_rms_n", u.force_noise_rms_n}, {"sensor_noise_rms_m", u.noise_rms_m}, {"delta_bic", u.delta_bic},
          {"at_bound", u.at_bound}, {"error_after_update", error_figures_json(o.updated.error)}};
}

nlohmann::json drop_errors_json(const DropErrors& e) {
  nlohmann::json c = nlohmann::json::array();
  for (int k = 0; k < 2; ++k) {
    const auto& m = e.measured_circle[static_cast<size_t>(k)];
    const auto& s = e.simulated_circle[static_cast<size_t>(k)];
    c.push_back({{"bearing", k}, {"valid", m.valid && s.valid}, {"measured_centre_m", m.centre_m},
                 {"simulated_centre_m", s.centre_m}, {"model_centre_m", e.model_centre_m[static_cast<size_t>(k)]},
                 {"sigma_m", m.sigma_m}, {"contact_points", m.points}});
  }
  return {{"error", error_figures_json(e.error)}, {"phase_c_cost", e.cost}, {"friction_coefficient", e.friction_coefficient},
          {"contact_circles", c}};
}

nlohmann::json score_json(const CorrectionScore& c) {
  return {{"unexplained_before_db", c.before_db}, {"unexplained_after_db", c.after_db}, {"noise_floor_db", c.noise_floor_db},
          {"absorbed_fraction", c.absorbed_fraction},
          {"absorbed_fraction_of_excess",
           std::isfinite(c.absorbed_fraction_of_excess) ? nlohmann::json(c.absorbed_fraction_of_excess) : nlohmann::json(nullptr)},
          {"points", c.points}};
}

}  // namespace

namespace {
// The part every record kind's document starts with.
nlohmann::json verdict_json(const std::vector<EffectAdded>& added, const ErrorFigures& before, const ErrorFigures& after,
                            const std::string& verdict, const std::vector<CandidateScore>& ranking,
                            const std::vector<std::string>& notes) {
  nlohmann::json j;
  j["effects_added"] = effects_added_json(added);
  j["error_before"] = error_figures_json(before);
  j["error_after"] = error_figures_json(after);
  j["verdict"] = verdict;
  j["ranking"] = candidates_json(ranking);
  j["structure"] = notes;
  return j;
}
}  // namespace

nlohmann::json error_figures_json(const ErrorFigures& e) {
  return {{"rms", e.rms}, {"spectral", e.spectral}, {"pearson", e.pearson}, {"statics", e.statics}};
}

nlohmann::json effects_added_json(const std::vector<EffectAdded>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& e : v) {
    nlohmann::json p = nlohmann::json::object();
    for (const auto& [k, x] : e.parameters) p[k] = x;
    a.push_back({{"name", e.name}, {"parameters", p}, {"evidence", e.evidence}, {"delta_bic", e.delta_bic}});
  }
  return a;
}

nlohmann::json unexplained_json(const std::vector<UnexplainedItem>& v) {
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

nlohmann::json learned_correction_json(const LearnedCorrectionSummary& s) {
  nlohmann::json j = {{"done", s.done},
                      {"note", s.note.empty() ? "learned correction: not a physical explanation, not part of the verdict" : s.note},
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

std::vector<std::string> drop_notes(const DropResidualOutcome& o) {
  std::vector<std::string> notes;
  if (o.levitated_analysed) {
    for (const auto& n : o.levitated.structure.notes) notes.push_back("levitated: " + n);
  } else {
    notes.push_back(o.levitated_note);
  }
  for (const auto& n : o.drop_notes) notes.push_back("drop: " + n);
  return notes;
}

std::vector<CandidateScore> drop_ranking(const DropResidualOutcome& o) {
  std::vector<CandidateScore> rank = o.levitated_analysed ? o.levitated.ranking : std::vector<CandidateScore>{};
  rank.insert(rank.end(), o.drop_ranking.begin(), o.drop_ranking.end());
  return rank;
}

nlohmann::json steady_residual_json(const SteadyData& d, const ResidualOutcome& o) {
  nlohmann::json j = verdict_json(o.effects_added, o.before.error, o.after.error, o.verdict, o.ranking, o.structure.notes);
  j["spin_hz"] = d.spin_hz;
  j["bic_before"] = o.before.bic;
  j["bic_after"] = o.after.bic;
  nlohmann::json fs = nlohmann::json::array();
  for (const auto& l : o.structure.full_spectrum)
    fs.push_back({{"plane", l.plane}, {"order", l.order}, {"forward_measured_m", l.forward_measured_m},
                  {"backward_measured_m", l.backward_measured_m}, {"forward_residual_m", l.forward_residual_m},
                  {"backward_residual_m", l.backward_residual_m}});
  j["full_spectrum"] = fs;
  j["model_update"] = model_update_json(o);
  j["unexplained"] = unexplained_json(o.unexplained);
  j["channel_rms_residual"] = o.structure_after.channel_rms_residual;
  j["orbit_residual_max_m"] = o.structure_after.orbit_residual_max_m;
  return j;
}

nlohmann::json drop_residual_json(const DropResidualOutcome& o) {
  nlohmann::json j = verdict_json(o.effects_added, o.before, o.after, o.verdict, drop_ranking(o), drop_notes(o));
  j["event_kind"] = "drop";
  nlohmann::json seg;
  if (o.levitated_analysed) {
    seg["levitated"] = {{"error_before", error_figures_json(o.levitated.before.error)},
                        {"error_after", error_figures_json(o.levitated.after.error)},
                        {"verdict", o.levitated.verdict},
                        {"model_update", model_update_json(o.levitated)}};
  }
  j["unexplained"] = unexplained_json(o.unexplained);
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
  seg["drop"] = {{"before", drop_errors_json(o.drop_before)}, {"after", drop_errors_json(o.drop_after)}, {"contact_law", o.contact_law},
                 {"runout", ro}, {"contact_compliance", co}};
  j["segments"] = seg;
  return j;
}

nlohmann::json sweep_residual_json(const SweepOutcome& o) {
  nlohmann::json j = verdict_json(o.effects_added, o.before.error, o.after.error, o.verdict, o.ranking, o.notes);
  j["accelerometer_axial_m"] = o.after.accel_axial_m;
  j["excited_axis"] = o.after.excited_axis;
  j["gain_scale"] = o.after.gain_scale;
  j["bic_before"] = o.before.bic;
  j["bic_after"] = o.after.bic;
  j["model_updating"] = sweep_update_json(o);
  return j;
}

std::string residual_text(const std::string& verdict, const ErrorFigures& b, const ErrorFigures& a,
                          const std::vector<CandidateScore>& rank, const std::vector<EffectAdded>& add,
                          const std::vector<std::string>& notes) {
  std::string out = "residual structure:\n";
  for (const auto& n : notes) out += "  " + n + "\n";
  out += "candidates (best first):\n";
  for (const auto& c : rank) out += "  " + candidate_text(c) + "\n";
  for (const auto& e : add) {
    out += "added " + e.name + ":";
    for (const auto& [k, x] : e.parameters) out += io::printf_text(" %s=%.4g", k.c_str(), x);
    out += "\n";
  }
  out += io::printf_text("error before: rms %.4g  spectral %.3g  pearson %.3f\n", b.rms, b.spectral, b.pearson);
  out += io::printf_text("error after : rms %.4g  spectral %.3g  pearson %.3f\n", a.rms, a.spectral, a.pearson);
  out += "verdict: " + verdict + "\n";
  return out;
}

std::string learned_correction_text(const LearnedCorrectionSummary& s) {
  std::string out = "learned correction (NOT a physical explanation; not part of the verdict):\n";
  if (!s.done) return out + "  skipped: " + s.skipped_why + "\n";
  const auto line = [&out](const char* what, const CorrectionScore& c) {
    out += io::printf_text("  %s: unexplained %.3g dB -> %.3g dB (noise floor %.3g dB), absorbed %.1f %%", what, c.before_db, c.after_db,
            c.noise_floor_db, 100.0 * c.absorbed_fraction);
    if (std::isfinite(c.absorbed_fraction_of_excess))
      out += io::printf_text(" (%.1f %% of the excess over the floor)", 100.0 * c.absorbed_fraction_of_excess);
    out += io::printf_text(", %d points\n", c.points);
  };
  out += "  " + s.domain + "\n  trained on " + s.trained_on + ", scored on " + s.scored_on + "\n";
  line("held out", s.held_out);
  if (s.has_reverse) line("reverse (parts swapped)", s.reverse_held_out);
  line("training part (optimistic)", s.training);
  for (const auto& g : s.groups)
    out += io::printf_text("  %-16s %.3g -> %.3g dB, lambda %.3g, %.1f effective of %d weights\n", g.name.c_str(), g.held_out.before_db,
            g.held_out.after_db, g.lambda, g.effective_parameters, g.weights);
  out += io::printf_text("  map: %d weights, %.1f effective parameters, trained on %d points\n", s.weights, s.effective_parameters,
          s.training_points);
  return out;
}

}  // namespace amb::host::residual
