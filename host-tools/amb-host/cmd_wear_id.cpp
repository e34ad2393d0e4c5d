// amb-host wear-id EVENT --model 2p|3p: journal-bearing wear identification from one steady
// speed (seed 002). Logic: host-tools/core/wearid/wear_identification.hpp.
#include <cmath>
#include <complex>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/events/event_board_choice.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "host-tools/core/ui/progress_lines.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"

namespace {

namespace wi = amb::host::wearid;

struct Args {
  std::string event;
  std::string model = "3p";
  std::string board;
  int doe = 9;
  int starts = 8;
  bool amb_planes = false;
  bool full_film = false;
  bool amb_nonlinear = false;
  bool amb_linear = false;
  bool second_harmonic = false;
  double model_error_1x = 0.0;
  double grid_tolerance = 2e-3;
  int film_samples = 32;
  int film_harmonics = 3;
  int threads = 2;
  double window_s = 2.0;
  bool json = false;
  bool force = false;
  bool quiet = false;
  std::vector<std::string> with;  // further records of the same bearing fitted together
};

nlohmann::json component(std::complex<double> z) {
  return {{"amplitude_um", std::abs(z) * 1e6}, {"phase_deg", std::arg(z) * 180.0 / M_PI}};
}

// [lo, hi], null where not finite (a rejected valley has no interval).
nlohmann::json interval(const std::array<double, 2>& v) {
  if (!std::isfinite(v[0]) || !std::isfinite(v[1])) return nullptr;
  return nlohmann::json::array({v[0], v[1]});
}

nlohmann::json valleys_json(const std::vector<wi::WearValley>& vs) {
  nlohmann::json out = nlohmann::json::array();
  for (const wi::WearValley& v : vs)
    out.push_back({{"d0_um", v.d0_um},
                   {"gamma_deg", v.gamma_deg},
                   {"beta_deg", v.beta_deg},
                   {"cost", v.cost},
                   {"chi2", std::isfinite(v.chi2) ? nlohmann::json(v.chi2) : nlohmann::json(nullptr)},
                   {"acceptable", v.acceptable},
                   {"d0_um_interval", interval(v.d0_interval_um)},
                   {"gamma_deg_interval", interval(v.gamma_interval_deg)},
                   {"beta_deg_interval", interval(v.beta_interval_deg)}});
  return out;
}

int run(const Args& a) {
  wi::WearIdOptions o;
  if (a.model == "2p") {
    o.model = amb::model::journal::WearModel::two_parameter;
  } else if (a.model == "3p") {
    o.model = amb::model::journal::WearModel::elliptical;
  } else {
    std::fprintf(stderr, "amb-host wear-id: error: --model must be 2p or 3p (got '%s')\n", a.model.c_str());
    return 1;
  }
  o.doe_points = a.doe;
  o.polished_starts = a.starts;
  o.threads = a.threads;
  o.window_s = a.window_s;
  o.use_amb_planes = a.amb_planes;
  o.second_harmonic = a.second_harmonic;
  o.full_film = a.full_film || a.second_harmonic;
  if (a.amb_nonlinear && a.amb_linear) {
    std::fprintf(stderr, "amb-host wear-id: error: --amb-nonlinear and --amb-linear exclude each other\n");
    return 1;
  }
  o.amb_nonlinear = !a.amb_linear;
  o.model_error_1x = a.model_error_1x;
  o.grid_tolerance = a.grid_tolerance;
  o.film_samples = a.film_samples;
  o.film_harmonics = a.film_harmonics;
  if (!a.quiet) o.progress = amb::host::ui::periodic_lines("wear-id", 5.0);
  if (const std::string why = o.check(); !why.empty()) {
    std::fprintf(stderr, "amb-host wear-id: error: %s\n", amb::host::cli::in_option_names(why, {{"doe_points", "--doe"}, {"polished_starts", "--starts"}, {"threads", "--threads"}, {"window_s", "--window"},
                                  {"film_samples", "--film-samples"}, {"film_harmonics", "--film-harmonics"},
                                  {"model_error_1x", "--model-error"}, {"full_film", "--full-film"}, {"grid_tolerance", "--grid-tolerance"}}).c_str());
    return 1;
  }
  wi::WearIdResult r;
  try {
    // Every record is read before any is analysed: a bad file is named whatever else is wrong.
    const amb::host::LoadedEvent ev = amb::host::load_event(a.event);
    std::vector<amb::host::LoadedEvent> others;
    for (const auto& w : a.with) others.push_back(amb::host::load_event(w));
    const amb::board::BoardConfig b = amb::host::board_for_loaded_event(ev, a.board, a.force);
    const wi::JournalMeasurement m = wi::measure_journal(ev, b, o.window_s);
    if (!a.quiet) std::fprintf(stderr, "wear-id: %s, %.3f Hz, static eccentricity %.3f, %d revolutions (the last %.2f s of %.2f s; --window), model %s\n",
                 a.event.c_str(), m.speed_hz, m.eccentricity, m.revolutions, m.window_s, m.available_s, a.model.c_str());
    std::vector<wi::JournalMeasurement> ms{m};
    for (size_t k = 0; k < others.size(); ++k) {
      const amb::host::LoadedEvent& other = others[k];
      const std::string& w = a.with[k];
      amb::host::check_board_matches_event_rig(amb::host::event_rig_name(other), b.plant.rig_name,
                                               a.board.empty() ? b.name : a.board, a.force);
      ms.push_back(wi::measure_journal(other, b, o.window_s));
      if (!a.quiet) std::fprintf(stderr, "wear-id: with %s, %.3f Hz, static eccentricity %.3f\n", w.c_str(), ms.back().speed_hz,
                   ms.back().eccentricity);
    }
    r = wi::identify_wear(b, ms, o);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "amb-host wear-id: error: %s\n", e.what());
    return 1;
  } catch (const amb::host::EventLoadError& e) {
    std::fprintf(stderr, "amb-host wear-id: error: %s\n", e.what());
    return 1;
  } catch (const amb::board::BoardError& e) {
    std::fprintf(stderr, "amb-host wear-id: error: --board: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host wear-id: error: %s\n", e.what());
    return 2;
  }
  if (!a.quiet) {
    std::fprintf(stderr, "wear-id: %s (dBIC %.1f, effect %.1f sigma; %s)\n",
                 r.wear_measurable ? "wear measured" : "no measurable wear", r.delta_bic, r.effect_sigma,
                 r.decision_reason.c_str());
    if (!r.identified) {
      std::string amb;
      for (const std::string& p : r.ambiguous) amb += (amb.empty() ? "" : ", ") + p;
      std::fprintf(stderr,
                   "wear-id: not identifiable from %s: %d valley%s the records cannot reject (chi2 within %.2f of the best, "
                   "%.0f %% level x scale %.2f); where the wear can be (%.0f %%): d0 %.1f..%.1f um, gamma %.1f..%.1f deg, "
                   "beta %.1f..%.1f deg; ambiguous: %s; flat direction at the best (d0 um, gamma deg, beta deg) = "
                   "(%.2f, %.2f, %.2f), 1-sigma %.3g along it\n",
                   r.records > 1 ? "these records" : "this record alone", r.acceptable_valleys,
                   r.acceptable_valleys == 1 ? "" : "s", r.chi2_scale * r.chi2_level, 100.0 * o.confidence, r.chi2_scale,
                   100.0 * o.confidence, r.d0_interval_um[0], r.d0_interval_um[1], r.gamma_interval_deg[0],
                   r.gamma_interval_deg[1], r.beta_interval_deg[0], r.beta_interval_deg[1], amb.empty() ? "none" : amb.c_str(),
                   r.flat_direction[0], r.flat_direction[1], r.flat_direction[2], r.flat_direction_sigma);
      for (const wi::WearValley& v : r.valleys)
        std::fprintf(stderr, "wear-id:   valley d0 %.2f um, gamma %.2f deg, beta %.2f deg: chi2 %.3g%s\n", v.d0_um, v.gamma_deg,
                     v.beta_deg, v.chi2, v.acceptable ? " (acceptable)" : " (rejected)");
      if (r.profile_restarts > 0)
        std::fprintf(stderr, "wear-id: %d profile point%s beat the best valley: polished from, valleys and verdict redone\n",
                     r.profile_restarts, r.profile_restarts == 1 ? "" : "s");
      if (r.records == 1)
        std::fprintf(stderr, "wear-id: fit it together with a record of the same bearing at another static eccentricity: --with EVENT2\n");
    }
    if (o.grid_tolerance > 0.0)
      std::fprintf(stderr, "wear-id: film grid %d x %d, estimated K/C error %.3f %% (tolerance %.3f %%%s); the board's %d x %d grid is %.2f %% off it\n",
                   r.grid_theta, r.grid_axial, 100.0 * r.grid_error_estimate, 100.0 * o.grid_tolerance,
                   r.grid_converged ? "" : ", NOT reached within the grid limits", r.coarse_grid_theta, r.coarse_grid_axial,
                   100.0 * r.coarse_grid_error);
    else
      std::fprintf(stderr, "wear-id: film grid %d x %d (the board's; --grid-tolerance 0: no refinement, error not estimated)\n",
                   r.grid_theta, r.grid_axial);
  }
  if (a.json) {
    nlohmann::json j = {
        {"model", r.model},
        {"d0_um", r.d0_um},
        {"d0_um_uncertainty", r.d0_uncertainty_um},
        {"gamma_deg", r.gamma_deg},
        {"gamma_deg_uncertainty", r.gamma_uncertainty_deg},
        {"beta_deg", r.beta_deg},
        {"beta_deg_uncertainty", r.beta_uncertainty_deg},
        {"cost", r.cost},
        {"evaluations", r.evaluations},
        {"doe_evaluations", r.doe_evaluations},
        {"records", r.records},
        {"wall_s", r.wall_s},
        {"stop_reason", r.stop_reason},
        {"bound_active", r.bound_active},
        {"speed_hz", r.measured.speed_hz},
        {"static_eccentricity", r.measured.eccentricity},
        {"analysed_s", r.measured.window_s},
        {"available_s", r.measured.available_s},
        {"used_amb_planes", r.used_amb_planes},
        {"used_full_film", r.used_full_film},
        {"used_2x", r.used_second_harmonic},
        {"model_error_1x", o.model_error_1x},
        {"amb_nonlinear", o.amb_nonlinear},
        {"film_harmonics", o.film_harmonics},
        {"refined_starts", r.refined_starts},
        {"identified", r.identified},
        {"flat_direction", {{"d0_um", r.flat_direction[0]}, {"gamma_deg", r.flat_direction[1]}, {"beta_deg", r.flat_direction[2]}}},
        {"flat_direction_sigma", r.flat_direction_sigma},
        {"acceptable_valleys", r.acceptable_valleys},
        {"valleys", valleys_json(r.valleys)},
        {"intervals",
         {{"d0_um", interval(r.d0_interval_um)},
          {"gamma_deg", interval(r.gamma_interval_deg)},
          {"beta_deg", interval(r.beta_interval_deg)},
          {"confidence", o.confidence}}},
        {"ambiguous", r.ambiguous},
        {"chi2",
         {{"min", r.chi2_min},
          {"dof", r.chi2_dof},
          {"level", r.chi2_level},
          {"scale", r.chi2_scale},
          {"film_error", r.chi2_film_error},
          {"ranking_passes", r.ranking_passes}}},
        {"profile_restarts", r.profile_restarts},
        {"wear_measurable", r.wear_measurable},
        {"verdict", r.wear_measurable ? "wear" : "no measurable wear"},
        {"model_comparison",
         {{"criterion", "residual loop engine::decide (default settings)"},
          {"unworn_cost", r.unworn_cost},
          {"delta_bic", r.delta_bic},
          {"effect_sigma", r.effect_sigma},
          {"reason", r.decision_reason}}},
        {"film_grid",
         {{"cells_theta", r.grid_theta},
          {"cells_axial", r.grid_axial},
          {"tolerance", o.grid_tolerance},
          {"error_estimate", r.grid_error_estimate},
          {"converged", r.grid_converged},
          {"board_cells_theta", r.coarse_grid_theta},
          {"board_cells_axial", r.coarse_grid_axial},
          {"board_grid_error", r.coarse_grid_error},
          {"correction_rounds", r.grid_iterations},
          {"intermediate_cells_theta", r.intermediate_grid_theta},
          {"intermediate_cells_axial", r.intermediate_grid_axial},
          {"intermediate_evaluations", r.intermediate_evaluations},
          {"fine_evaluations", r.fine_evaluations},
          {"wall_s", r.grid_wall_s}}},
        {"spectrum",
         {{"measured", {{"forward", component(r.measured.spectrum.forward_m)}, {"backward", component(r.measured.spectrum.backward_m)}}},
          {"fitted", {{"forward", component(r.fitted.forward_m)}, {"backward", component(r.fitted.backward_m)}}},
          {"noise_um", r.measured.noise_m * 1e6},
          {"measured_2x", {{"forward", component(r.measured.second_harmonic.forward_m)},
                           {"backward", component(r.measured.second_harmonic.backward_m)}}},
          {"noise_2x_um", r.measured.noise_2x_m * 1e6}}}};
    if (r.used_full_film)
      j["spectrum"]["fitted_2x"] = {{"forward", component(r.fitted_2x.forward_m)}, {"backward", component(r.fitted_2x.backward_m)}};
    // Non-finite uncertainties (Jacobian failed) become null.
    for (const char* k : {"d0_um_uncertainty", "gamma_deg_uncertainty", "beta_deg_uncertainty"})
      if (!std::isfinite(j[k].get<double>())) j[k] = nullptr;
    for (const char* k : {"unworn_cost", "delta_bic", "effect_sigma"})
      if (!std::isfinite(j["model_comparison"][k].get<double>())) j["model_comparison"][k] = nullptr;
    if (!std::isfinite(j["flat_direction_sigma"].get<double>())) j["flat_direction_sigma"] = nullptr;
    for (const char* k : {"min", "level"})
      if (!std::isfinite(j["chi2"][k].get<double>())) j["chi2"][k] = nullptr;
    for (const char* k : {"error_estimate", "board_grid_error"})
      if (!std::isfinite(j["film_grid"][k].get<double>())) j["film_grid"][k] = nullptr;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("wear (%s model): d0 = %.2f +- %.2f um, gamma = %.2f +- %.2f deg, beta = %.2f +- %.2f deg%s\n",
                r.model.c_str(), r.d0_um, r.d0_uncertainty_um, r.gamma_deg, r.gamma_uncertainty_deg, r.beta_deg,
                r.beta_uncertainty_deg, r.model == "2p" ? " (span implied by the depth)" : "");
    std::printf("cost %.3e after %d evaluations (%d in the DOE), %.2f s; optimiser: %s%s\n", r.cost, r.evaluations,
                r.doe_evaluations, r.wall_s, r.stop_reason.c_str(), r.bound_active ? "; a parameter is on its bound" : "");
    std::printf("+1x: measured %.3f um @ %.1f deg, model %.3f um @ %.1f deg\n", std::abs(r.measured.spectrum.forward_m) * 1e6,
                std::arg(r.measured.spectrum.forward_m) * 180 / M_PI, std::abs(r.fitted.forward_m) * 1e6,
                std::arg(r.fitted.forward_m) * 180 / M_PI);
    std::printf("-1x: measured %.3f um @ %.1f deg, model %.3f um @ %.1f deg\n", std::abs(r.measured.spectrum.backward_m) * 1e6,
                std::arg(r.measured.spectrum.backward_m) * 180 / M_PI, std::abs(r.fitted.backward_m) * 1e6,
                std::arg(r.fitted.backward_m) * 180 / M_PI);
    if (r.used_full_film) {
      std::printf("+2x: measured %.3f um @ %.1f deg, model %.3f um @ %.1f deg%s\n",
                  std::abs(r.measured.second_harmonic.forward_m) * 1e6, std::arg(r.measured.second_harmonic.forward_m) * 180 / M_PI,
                  std::abs(r.fitted_2x.forward_m) * 1e6, std::arg(r.fitted_2x.forward_m) * 180 / M_PI,
                  r.used_second_harmonic ? "" : " (not fitted)");
      std::printf("-2x: measured %.3f um @ %.1f deg, model %.3f um @ %.1f deg\n",
                  std::abs(r.measured.second_harmonic.backward_m) * 1e6, std::arg(r.measured.second_harmonic.backward_m) * 180 / M_PI,
                  std::abs(r.fitted_2x.backward_m) * 1e6, std::arg(r.fitted_2x.backward_m) * 180 / M_PI);
    }
  }
  return 0;
}

void declare(CLI::App& sub, Args& args) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("event", args.event,
                                "steady record (measured event .json/.csv or stem) with journal probes and key phasor")
                     ->required(),
                 "measured-event");
  sub.add_option("--model", args.model, "wear model: 2p (depth, position; span tied to depth) or 3p (elliptical)")
      ->capture_default_str()
      ->check(CLI::IsMember({"2p", "3p"}));
  hc::input_file(sub.add_option("--board", args.board, "board to use instead of the one the event's rig names"), "board");
  sub.add_flag("--force", args.force, "use --board even when it is a board of another rig than the event's");
  hc::whole(sub.add_option("--doe", args.doe, "design-of-experiments grid points per parameter"), 2, 50);
  hc::whole(sub.add_option("--starts", args.starts, "best DOE points polished by the local optimiser"), 1, 1000);
  hc::whole(sub.add_option("--threads", args.threads, "threads"), 1, 64);
  hc::positive(sub.add_option("--window", args.window_s, "analysed time at the end of the record, s"), 3600.0, "s");
  hc::input_file(sub.add_option("--with", args.with,
                                "further records of the same bearing (e.g. the other static eccentricity) fitted together"),
                 "measured-event");
  sub.add_flag("--amb-planes", args.amb_planes,
               "also fit the +1x/-1x at the AMB sensor planes (default: journal probes only, as the seed)");
  sub.add_flag("--full-film", args.full_film,
               "forward model with the full (nonlinear) Reynolds film by harmonic balance instead of its "
               "linearisation (default: linear, as the seed)");
  sub.add_flag("--2x", args.second_harmonic,
               "also fit the +2x/-2x at the journal probes (the film's second-order response; implies --full-film)");
  sub.add_flag("--amb-nonlinear", args.amb_nonlinear,
               "full film: the AMBs' force law in the harmonic balance too (its own 2x; the default)");
  sub.add_flag("--amb-linear", args.amb_linear,
               "full film: the AMBs linearised at their operating point (no 2x of their own)");
  hc::whole(sub.add_option("--film-samples", args.film_samples, "full film: Reynolds solves per revolution of the orbit"), 8, 512);
  hc::whole(sub.add_option("--film-harmonics", args.film_harmonics,
                           "full film: highest harmonic of the spin in the harmonic balance (3: the orbit's 3x feeds "
                           "the film's 2x)"),
            2, 6);
  hc::real(sub.add_option("--model-error", args.model_error_1x,
                          "relative model-error floor of the 1x residuals, e.g. 0.0025 (0: the seed's equal weights)"),
           0.0, 0.49);
  hc::real(sub.add_option("--grid-tolerance", args.grid_tolerance,
                          "film grid refined at the optimum until the estimated K/C error is below this (relative; "
                          "0: the board's grid only)"),
           0.0, 0.49);
  sub.add_flag("--json", args.json, "print the figures as JSON");
  sub.add_flag("--quiet", args.quiet, "no progress lines on stderr");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "wear-id", "identify journal-bearing wear (d0, gamma, beta) from one steady speed (seed 002)", declare, run);

}  // namespace
