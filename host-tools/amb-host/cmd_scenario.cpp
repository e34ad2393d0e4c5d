// amb-host scenario: the end-to-end drop scenario on the simulated rig (the main job).
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/scenario/drop_scenario.hpp"
#include "host-tools/core/scenario/loop_rating.hpp"

namespace {

int run(const amb::host::DropScenarioOptions& opt_in, bool json, bool quiet) {
  amb::host::DropScenarioOptions opt = opt_in;
  // Stages on stderr (also with --json: stdout carries the JSON only), one line each.
  if (!quiet) opt.progress = [](const std::string& s) { std::fprintf(stderr, "scenario: %s\n", s.c_str()); };
  const auto s = amb::host::run_drop_scenario(opt);
  // The loop's ISO 14839-3 rating with the board's own delay (exact sampled analysis).
  const amb::host::LoopRating lr = amb::host::rate_loop(amb::board::load_board(opt.board));
  if (json) {
    nlohmann::json j;
    j["board"] = s.board;
    j["loop_rating"] = {{"rate_hz", lr.rate_hz}, {"loop_delay_periods", lr.loop_delay_periods}, {"stable", lr.stable},
                        {"sensitivity_peak", lr.sensitivity_peak}, {"sensitivity_peak_db", lr.sensitivity_peak_db},
                        {"peak_hz", lr.peak_hz}, {"peak_axis", lr.peak_axis}, {"zone", lr.zone},
                        {"rotor_mode_hz", lr.rotor_mode_hz}, {"rotor_mode_zeta", lr.rotor_mode_zeta}};
    j["levitated"] = s.levitated;
    j["liftoff_s"] = s.liftoff_s;
    j["reached_speed"] = s.reached_speed;
    j["speed_at_cut_hz"] = s.speed_at_cut_hz;
    auto num_or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    j["speed_source"] = s.speed_source;
    j["tracked_speed_at_cut_hz"] = num_or_null(s.tracked_speed_at_cut_hz);
    j["tracked_speed_confidence_at_cut"] = s.tracked_confidence_at_cut;
    j["tracked_speed_lost_at_cut"] = s.tracked_lost_at_cut;
    j["tracked_speed_error_at_cut"] = num_or_null((s.tracked_speed_at_cut_hz - s.speed_at_cut_hz) / s.speed_at_cut_hz);
    j["speed_disagreements"] = s.speed_disagreements;
    j["steady_orbit_max_m"] = s.steady_orbit_max_m;
    j["aux_clearance_m"] = s.aux_clearance_m;
    j["fault_detected"] = s.fault_detected;
    j["fault_reason"] = s.fault_reason;
    j["detection_delay_ms"] = s.detection_delay_ms;
    j["max_contact_force_n"] = s.max_contact_force_n;
    j["speed_end_hz"] = s.speed_end_hz;
    j["friction_energy_j"] = s.friction_energy_j;
    j["final_state"] = s.final_state;
    j["loop_periods"] = s.loop_periods;
    j["loop_overruns"] = s.loop_overruns;
    j["simulated_s"] = s.simulated_s;
    j["wall_s"] = s.wall_s;
    j["event"] = {{"captured", s.event_captured}, {"path", s.event_path}, {"export", s.event_export_stem},
                  {"trigger_cause", s.trigger_cause}, {"trigger_delay_ms", s.trigger_delay_ms},
                  {"speed_at_trigger_hz", num_or_null(s.event_speed_at_trigger_hz)},
                  {"speed_confidence", s.event_speed_confidence}, {"speed_lost", s.event_speed_lost},
                  {"phase_b", {{"fault", s.phase_b_fault}, {"confidence", s.phase_b_confidence}, {"summary", s.phase_b_summary}}}};
    j["fit"] = {{"ran", s.fitted}, {"friction_coefficient", s.friction_coefficient}, {"cost", s.fit_cost},
                {"evaluations", s.fit_evaluations}, {"wall_s", s.fit_wall_s}, {"converged", s.fit_converged},
                {"friction_uncertainty", s.friction_uncertainty}, {"bound_active", s.fit_bound_active},
                {"contact_law", s.contact_law},
                {"rotor_structure", {{"modes_per_plane", s.fit_rotor_modes_per_plane},
                                     {"model", s.fit_rotor_modes_per_plane == 2 ? "rigid" : "flexible"}}},
                {"whirl", {{{"direction", s.whirl_direction[0]}, {"frequency_hz", s.whirl_frequency_hz[0]}},
                           {{"direction", s.whirl_direction[1]}, {"frequency_hz", s.whirl_frequency_hz[1]}}}},
                {"rubbing_s", {{"swing", s.rubbing_s[0]}, {"forward", s.rubbing_s[1]}, {"backward", s.rubbing_s[2]}}},
                {"error", s.fit_error}};
    j["wear_record"] = {{"written", s.wear_written}, {"path", s.wear_path}, {"sequence", s.wear_sequence},
                        {"peak_force_n", s.wear_peak_force_n}, {"friction_energy_j", s.wear_friction_energy_j},
                        {"load_sum_n", s.load_sum_n}, {"load_peak_bin_deg", s.load_peak_bin_deg},
                        {"load_whirl_hz", s.load_whirl_hz}};
    j["report"] = s.report_path;
    j["residual"] = {{"ran", s.residual_ran}, {"record", s.residual_record}, {"verdict", s.residual_verdict},
                     {"error_before", {{"rms", s.residual_before[0]}, {"spectral", s.residual_before[1]}, {"pearson", s.residual_before[2]}}},
                     {"error_after", {{"rms", s.residual_after[0]}, {"spectral", s.residual_after[1]}, {"pearson", s.residual_after[2]}}},
                     {"error", s.residual_error}};
    auto f4 = [](const std::array<double, 4>& e) {
      return nlohmann::json{{"rms", e[0]}, {"spectral", e[1]}, {"pearson", e[2]}, {"statics", e[3]}};
    };
    j["drop_residual"] = {{"ran", s.drop_residual_ran}, {"record", s.drop_residual_record},
                          {"verdict", s.drop_residual_verdict}, {"error_before", f4(s.drop_residual_before)},
                          {"error_after", f4(s.drop_residual_after)}, {"error", s.drop_residual_error}};
    nlohmann::json added = nlohmann::json::array();
    for (const auto& [name, params] : s.drop_residual_added) {
      nlohmann::json p = nlohmann::json::object();
      for (const auto& [k, v] : params) p[k] = v;
      added.push_back({{"name", name}, {"parameters", p}});
    }
    j["drop_residual"]["effects_added"] = added;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("Drop scenario on %s (simulated rig, sim HAL backend)\n", s.board.c_str());
    std::printf("  loop rating        : ISO 14839-3 peak %.2f (%.1f dB) at %.3g Hz, zone %s, with the board's delay of %.2f "
                "periods (%s)\n", lr.sensitivity_peak, lr.sensitivity_peak_db, lr.peak_hz, lr.zone.c_str(),
                lr.loop_delay_periods, lr.stable ? "stable" : "UNSTABLE");
    std::printf("  lift-off           : %s in %.3f s\n", s.levitated ? "levitated" : "FAILED", s.liftoff_s);
    std::printf("  spin-up            : %s, %.1f Hz (%.0f rpm) at the cut\n", s.reached_speed ? "reached" : "FAILED",
                s.speed_at_cut_hz, s.speed_at_cut_hz * 60.0);
    std::printf("  speed at the cut   : plant %.3f Hz, board tracker %.3f Hz (%+.2f %%, confidence %.2f%s); speed source %s\n",
                s.speed_at_cut_hz, s.tracked_speed_at_cut_hz,
                100.0 * (s.tracked_speed_at_cut_hz - s.speed_at_cut_hz) / s.speed_at_cut_hz, s.tracked_confidence_at_cut,
                s.tracked_lost_at_cut ? ", LOST" : "", s.speed_source.c_str());
    std::printf("  steady orbit       : max %.1f um at the sensor planes (aux clearance %.0f um)\n",
                s.steady_orbit_max_m * 1e6, s.aux_clearance_m * 1e6);
    std::printf("  AMB cut            : t = %.3f s; firmware %s after %.1f ms (%s)\n", s.cut_time_s,
                s.fault_detected ? "entered the safe state" : "did NOT detect it", s.detection_delay_ms,
                s.fault_reason.c_str());
    std::printf("  landing            : peak contact force %.0f N, friction energy %.2f J, speed %.1f -> %.1f Hz\n",
                s.max_contact_force_n, s.friction_energy_j, s.speed_at_cut_hz, s.speed_end_hz);
    std::printf("  firmware           : final state %s, %llu loop periods, %llu overruns\n", s.final_state.c_str(),
                static_cast<unsigned long long>(s.loop_periods), static_cast<unsigned long long>(s.loop_overruns));
    if (s.event_captured) {
      std::printf("  Phase A capture    : event %s, trigger %s %.1f ms after the cut\n", s.event_path.c_str(),
                  s.trigger_cause.c_str(), s.trigger_delay_ms);
      std::printf("  event speed stamp  : %.3f Hz, confidence %.2f%s\n", s.event_speed_at_trigger_hz,
                  s.event_speed_confidence, s.event_speed_lost ? ", LOST" : "");
      std::printf("  Phase B verdict    : %s (confidence %.2f) %s\n", s.phase_b_fault.c_str(), s.phase_b_confidence,
                  s.phase_b_summary.c_str());
      std::printf("  exchange format    : %s.csv / .json\n", s.event_export_stem.c_str());
    } else {
      std::printf("  Phase A capture    : NO event captured\n");
    }
    if (s.fitted)
      std::printf("  Phase C fit        : friction coefficient %.4f +- %.4f (%s contact, %s rotor), rubbing swing %.3f s / forward %.3f s / "
                  "backward %.3f s,\n"
                  "                       whirl A %s %.1f Hz, B %s %.1f Hz; cost %.4g, %d evaluations in %.1f s, %s\n",
                  s.friction_coefficient, s.friction_uncertainty, s.contact_law.c_str(),
                  s.fit_rotor_modes_per_plane == 2 ? "rigid" : "flexible", s.rubbing_s[0], s.rubbing_s[1],
                  s.rubbing_s[2], s.whirl_direction[0].c_str(), s.whirl_frequency_hz[0], s.whirl_direction[1].c_str(),
                  s.whirl_frequency_hz[1], s.fit_cost, s.fit_evaluations, s.fit_wall_s,
                  s.fit_converged ? "converged" : (s.fit_bound_active ? "BOUND ACTIVE" : "not converged"));
    else if (!s.fit_error.empty())
      std::printf("  Phase C fit        : not run: %s\n", s.fit_error.c_str());
    if (s.wear_written)
      std::printf("  Phase E wear record: %s (sequence %u): peak contact force %.0f N, friction energy %.2f J\n",
                  s.wear_path.c_str(), s.wear_sequence, s.wear_peak_force_n, s.wear_friction_energy_j);
    if (s.wear_written)
      std::printf("  load map (1 deg)   : bearing A sum %.3g N, peak at %d deg; bearing B sum %.3g N, peak at %d deg\n",
                  s.load_sum_n[0], s.load_peak_bin_deg[0], s.load_sum_n[1], s.load_peak_bin_deg[1]);
    if (s.residual_ran)
      std::printf("  residual loop      : undeclared effect in a steady run -> added: %s\n"
                  "                       error before rms %.4f / spectral %.2f dB / pearson %.3f; after %.4f / %.2f dB / %.3f\n",
                  s.residual_verdict.c_str(), s.residual_before[0], s.residual_before[1], s.residual_before[2],
                  s.residual_after[0], s.residual_after[1], s.residual_after[2]);
    else if (!s.residual_error.empty())
      std::printf("  residual loop      : not run: %s\n", s.residual_error.c_str());
    if (s.drop_residual_ran)
      std::printf("  residual, drop     : undeclared effect in a drop event -> added: %s\n"
                  "                       error before rms %.4f / spectral %.2f dB / pearson %.3f / contact misfit %.4f\n"
                  "                       error after  rms %.4f / spectral %.2f dB / pearson %.3f / contact misfit %.4f\n",
                  s.drop_residual_verdict.c_str(), s.drop_residual_before[0], s.drop_residual_before[1],
                  s.drop_residual_before[2], s.drop_residual_before[3], s.drop_residual_after[0], s.drop_residual_after[1],
                  s.drop_residual_after[2], s.drop_residual_after[3]);
    if (s.drop_residual_ran)
      for (const auto& [name, params] : s.drop_residual_added) {
        std::printf("                       %s:", name.c_str());
        for (const auto& [k, v] : params)
          if (k.size() > 2 && k.compare(k.size() - 2, 2, "_m") == 0) std::printf(" %s %.1f um", k.c_str(), v * 1e6);
          else std::printf(" %s %.4g", k.c_str(), v);
        std::printf("\n");
      }
    if (!s.drop_residual_ran && !s.drop_residual_error.empty())
      std::printf("  residual, drop     : not run: %s\n", s.drop_residual_error.c_str());
    std::printf("  run                : %.2f s simulated in %.2f s wall (%.1fx real time)\n", s.simulated_s, s.wall_s,
                s.simulated_s / s.wall_s);
  }
  if (!s.report_path.empty()) std::fprintf(json ? stderr : stdout, "report: %s\n", s.report_path.c_str());
  const bool ok = s.levitated && s.reached_speed && s.fault_detected && s.event_captured;
  return ok ? 0 : 2;
}

const amb::host::Registration reg{
    "scenario", "run the end-to-end drop scenario on the simulated rig (the main job)",
    [](CLI::App& sub, std::function<int()>& run_fn) {
      auto opt = std::make_shared<amb::host::DropScenarioOptions>();
      auto json = std::make_shared<bool>(false);
      auto quiet = std::make_shared<bool>(false);
      namespace hc = amb::host::cli;
      hc::input_file(sub.add_option("--board", opt->board, "board name or board file")->capture_default_str(), "board");
      hc::real(sub.add_option("--hold-s", opt->hold_s, "time at speed before the AMBs are cut, s"), 0.0, 60.0, "s");
      hc::real(sub.add_option("--after-cut-s", opt->after_cut_s, "simulated time after the cut, s"), 0.0, 60.0, "s");
      hc::whole(sub.add_option("--seed", opt->noise_seed, "sensor-noise seed"), 0, 9.0e15);
      sub.add_option("--speed-source", opt->speed_source,
                     "board speed source: tracker (tachless, default), tach, command; empty: the board file's")
          ->check(CLI::IsMember({"tracker", "tach", "command", ""}));
      hc::output_path(sub.add_option("--out", opt->out_dir, "directory for the event, its export and the report"));
      sub.add_flag("!--no-fit", opt->fit, "skip the Phase C fit");
      sub.add_flag("!--no-residual", opt->residual, "skip the steady run with an undeclared effect");
      sub.add_flag("--json", *json, "print the figures as JSON");
      sub.add_flag("--quiet", *quiet, "no stage lines on stderr");
      run_fn = [opt, json, quiet] { return run(*opt, *json, *quiet); };
    }};

}  // namespace
