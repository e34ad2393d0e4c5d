// amb-host fit EVENT: Phase C of seed 000: fit the multibody drop model to a measured drop
// (measured-event format) by implicit filtering; optionally fold the fitted event into a
// wear record (Phase D/E). Logic: host-tools/core/fit/, host-tools/core/wear/.
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/events/event_board_choice.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "host-tools/core/ui/progress_lines.hpp"
#include "host-tools/core/wear/wear_update.hpp"

namespace {

struct Args {
  std::string event;
  std::string board;
  bool json = false;
  double window_s = 0.4;
  bool fit_restitution = false;
  bool fit_offset = false;
  bool fit_law_shape = false;
  bool lock_in_cost = false;
  bool friction_from_fit = false;
  bool force = false;
  bool quiet = false;
  std::string wear_in, wear_out;
};

int bad_input(const std::string& what) {
  std::fprintf(stderr, "amb-host fit: error: %s\n", what.c_str());
  return 1;
}

nlohmann::json durations(const amb::model::drop::RubbingDurations& d) {
  return {{"swing", d.swing_s}, {"forward", d.forward_s}, {"backward", d.backward_s}};
}

int run(const Args& a) {
  namespace hf = amb::host::fit;
  namespace hw = amb::host::wear;
  amb::board::BoardConfig board;
  hf::DropMeasurement m;
  try {
    const amb::host::LoadedEvent ev = amb::host::load_event(a.event);
    board = amb::host::board_for_loaded_event(ev, a.board, a.force);
    m = hf::drop_measurement_from_event(ev);
  } catch (const std::exception& e) {
    return bad_input(e.what());
  }
  // The wear record is read (and the output's folder checked) before the fit: bad input there
  // must not cost a fit.
  amb::fw::WearRecord prev;
  if (!a.wear_in.empty() && a.wear_out.empty()) return bad_input("--wear-in needs --wear-out (where the updated record goes)");
  if (!a.wear_out.empty()) {
    const std::filesystem::path parent = std::filesystem::path(a.wear_out).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent))
      return bad_input("--wear-out '" + a.wear_out + "': folder '" + parent.string() + "' does not exist");
  }
  if (!a.wear_in.empty()) {
    std::ifstream in(a.wear_in, std::ios::binary);
    if (!in) return bad_input("--wear-in '" + a.wear_in + "' cannot be read");
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string err;
    if (!amb::fw::decode_wear_record(bytes, prev, err)) return bad_input("--wear-in '" + a.wear_in + "': " + err);
    if (prev.board_name != board.name)
      return bad_input("--wear-in '" + a.wear_in + "' is the wear record of board '" + prev.board_name + "', not of '" +
                       board.name + "'");
  }
  hf::DropFitOptions o;
  o.max_window_s = a.window_s;
  o.fit_restitution = a.fit_restitution;
  o.fit_centre_offset = a.fit_offset;
  o.fit_slip_regularisation = a.fit_law_shape;
  o.fit_contact_exponent = a.fit_law_shape;
  o.weights.lock_in_features = a.lock_in_cost;
  o.friction_from_contact_forces = !a.friction_from_fit;
  if (!a.quiet) o.progress = amb::host::ui::periodic_lines("fit");
  if (const std::string e = o.check(); !e.empty()) return bad_input(amb::host::cli::in_option_names(e, {{"max_window_s", "--window"}}));
  hf::DropFitResult r;
  try {
    r = hf::fit_drop(m, board, o);
  } catch (const std::invalid_argument& e) {
    return bad_input(e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host fit: fit failed: %s\n", e.what());
    return 2;
  }

  // Optional Phase D/E: fold the fitted event into a wear record.
  std::string wear_note;
  if (!a.wear_out.empty()) {
    hw::WearEvent ev;
    ev.load = hw::event_load(r.trace.contact_steps);
    ev.rubbing = r.rubbing;
    ev.friction_coefficient = r.friction_coefficient;
    const auto now = std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    amb::fw::WearRecord next;
    try {
      next = hw::update_wear_record(prev, ev, board.name, now, hw::WearOptions{});
    } catch (const std::invalid_argument& e) {
      return bad_input(e.what());
    }
    // Written whole or not at all: a temporary file renamed over the target.
    const auto bytes = amb::fw::encode_wear_record(next);
    const std::string tmp = a.wear_out + ".tmp";
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      if (!out) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        std::fprintf(stderr, "amb-host fit: error: --wear-out '%s' cannot be written\n", a.wear_out.c_str());
        return 2;
      }
    }
    std::filesystem::rename(tmp, a.wear_out);
    wear_note = "wear record sequence " + std::to_string(next.sequence) + " written to " + a.wear_out;
  }

  if (a.json) {
    nlohmann::json j;
    j["friction_coefficient"] = r.friction_coefficient;
    j["rubbing_s"] = durations(r.rubbing[0]);
    j["rubbing_s_per_bearing"] = {durations(r.rubbing[0]), durations(r.rubbing[1])};
    j["measured_rubbing_s_per_bearing"] = {durations(r.measured_rubbing[0]), durations(r.measured_rubbing[1])};
    j["cost"] = r.cost.total;
    j["cost_terms"] = {{"rubbing", r.cost.rubbing}, {"orbit", r.cost.orbit},   {"speed", r.cost.speed},
                       {"spin_down", r.cost.spin_down}, {"contact", r.cost.contact}, {"whirl", r.cost.whirl},
                       {"bounce", r.cost.bounce}};
    j["friction_uncertainty"] = r.friction_uncertainty;
    j["friction_method"] = r.friction_method;
    {
      const auto& fe = r.friction_estimate;
      nlohmann::json windows = nlohmann::json::array();
      for (const auto& w : fe.windows)
        windows.push_back({{"bearing", w.bearing}, {"start_s", w.start_s}, {"normal_impulse_n_s", w.normal_impulse_n_s},
                           {"friction_impulse_n_s", w.friction_impulse_n_s}, {"ratio", w.ratio}, {"sliding", w.sliding},
                           {"next_to_rolling", w.next_to_rolling}});
      j["friction_estimate"] = {{"valid", fe.valid},
                                {"friction", fe.friction},
                                {"uncertainty", fe.uncertainty},
                                {"standard_error", fe.standard_error},
                                {"smoothing_change", fe.smoothing_change},
                                {"windows_used", fe.windows_used},
                                {"windows_total", fe.windows_total},
                                {"window_s", fe.window_s},
                                {"sliding_time_s", fe.sliding_time_s},
                                {"measured_spin_down_rad_s2", fe.measured_spin_down_rad_s2},
                                {"force_spin_down_rad_s2", fe.force_spin_down_rad_s2},
                                {"force_spin_down_scatter_rad_s2", fe.force_spin_down_scatter_rad_s2},
                                {"synchronous_removed", fe.synchronous_removed},
                                {"synchronous_force_n", fe.synchronous_force_n},
                                {"synchronous_moment_n_m", fe.synchronous_moment_n_m},
                                {"bending_modes", fe.bending_modes},
                                {"rotor_choice", fe.rotor_choice},
                                {"free_flight_samples", fe.free_flight_samples},
                                {"free_flight_force_rms_n", {{"rigid", fe.free_flight_force_rms_n[0]}, {"bent", fe.free_flight_force_rms_n[1]}}},
                                {"free_flight_noise_rms_n", {{"rigid", fe.free_flight_noise_rms_n[0]}, {"bent", fe.free_flight_noise_rms_n[1]}}},
                                {"note", fe.note},
                                {"windows", windows}};
    }
    j["bound_active"] = r.bound_active;
    j["contact_law"] = r.contact_law;
    j["contact_stiffness_n_per_m"] = r.contact_stiffness_n_per_m;
    j["contact_damping_n_s_per_m"] = r.contact_damping_n_s_per_m;
    j["ring_drag_n_m"] = r.ring_drag_n_m;
    j["spin_down_rad_s2"] = r.spin_down_rad_s2;
    j["fitted_spin_down_rad_s2"] = r.fitted_spin_down_rad_s2;
    j["polish_evaluations"] = r.polish_evaluations;
    nlohmann::json unknowns = nlohmann::json::array();
    for (const auto& u : r.unknowns)
      unknowns.push_back({{"name", u.name}, {"value", u.value}, {"uncertainty", u.uncertainty}, {"lower", u.lower},
                          {"upper", u.upper}, {"bound_active", u.bound_active}});
    j["unknowns"] = unknowns;
    const auto whirl_json = [](const std::array<hf::WhirlSummary, 2>& w) {
      nlohmann::json list = nlohmann::json::array();
      for (const auto& x : w)
        list.push_back({{"direction", x.direction}, {"frequency_hz", x.frequency_hz}, {"onset_s", x.onset_s},
                     {"contact_share", x.contact_share}, {"whirl_rate_rad_s", x.whirl_rate_rad_s},
                     {"bounce_rate_per_s", x.bounce_rate_per_s}});
      return list;
    };
    j["whirl"] = whirl_json(r.whirl);
    j["fitted_whirl"] = whirl_json(r.fitted_whirl);
    const auto lock_in_json = [](const hf::LockInFeatures& f) {
      return nlohmann::json{{"valid", f.valid},
                            {"own", f.own},
                            {"start_s", f.start_s},
                            {"speed_level_rad_s", f.speed_level_rad_s},
                            {"spin_down_rad_s2", f.spin_down_rad_s2},
                            {"whirling", {f.whirling[0], f.whirling[1]}},
                            {"centripetal_m_s2", {f.centripetal_m_s2[0], f.centripetal_m_s2[1]}},
                            {"penetration_m", {f.penetration_m[0], f.penetration_m[1]}}};
    };
    j["cost_lock_in"] = r.cost.lock_in;
    j["lock_in"] = lock_in_json(r.lock_in);
    j["fitted_lock_in"] = lock_in_json(r.fitted_lock_in);
    nlohmann::json trials = nlohmann::json::array();
    for (const auto& t : r.structure_trials)
      trials.push_back({{"modes_per_plane", t.modes_per_plane}, {"cost", t.cost}, {"converged", t.converged}, {"bound_active", t.bound_active}});
    j["rotor_structure"] = {{"modes_per_plane", r.rotor_modes_per_plane},
                            {"model", r.rotor_modes_per_plane == 2 ? "rigid" : "flexible"},
                            {"trials", trials}};
    j["evaluations"] = r.evaluations;
    j["wall_s"] = r.wall_s;
    j["converged"] = r.converged;
    j["stop_reason"] = r.stop_reason;
    j["restitution"] = r.restitution;
    j["centre_offset_m"] = {r.centre_offset_m[0], r.centre_offset_m[1]};
    j["cost_history"] = r.cost_history;
    if (!wear_note.empty()) j["wear"] = wear_note;
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("friction coefficient %.4f +- %.4f (%s contact), cost %.4f (rubbing %.4f, orbit %.4f, speed %.4f, spin-down %.4f, "
              "contact %.4f, whirl %.4f, bounce %.4f)\n",
              r.friction_coefficient, r.friction_uncertainty, r.contact_law.c_str(), r.cost.total, r.cost.rubbing, r.cost.orbit,
              r.cost.speed, r.cost.spin_down, r.cost.contact, r.cost.whirl, r.cost.bounce);
  for (const auto& u : r.unknowns)
    std::printf("  %s = %.6g +- %.3g [%.4g, %.4g]%s\n", u.name.c_str(), u.value, u.uncertainty, u.lower, u.upper,
                u.bound_active ? " BOUND ACTIVE" : "");
  std::printf("friction from %s", r.friction_method.c_str());
  if (r.friction_estimate.valid)
    std::printf(": %.4f +- %.4f over %d of %d windows of %.2f ms (%.3f s sliding; spin-down there %.2f rad/s^2 measured, %.2f from the contact forces)",
                r.friction_estimate.friction, r.friction_estimate.uncertainty, r.friction_estimate.windows_used,
                r.friction_estimate.windows_total, 1e3 * r.friction_estimate.window_s, r.friction_estimate.sliding_time_s, r.friction_estimate.measured_spin_down_rad_s2,
                r.friction_estimate.force_spin_down_rad_s2);
  std::printf("\n");
  std::printf("spin-down %.3f rad/s^2 measured, %.3f fitted\n", r.spin_down_rad_s2, r.fitted_spin_down_rad_s2);
  for (size_t b = 0; b < 2; ++b)
    std::printf("aux bearing %zu whirl: %s at %.1f Hz from %.4f s (fitted model: %s at %.1f Hz)\n", b + 1,
                r.whirl[b].direction.c_str(), r.whirl[b].frequency_hz, r.whirl[b].onset_s, r.fitted_whirl[b].direction.c_str(),
                r.fitted_whirl[b].frequency_hz);
  for (size_t b = 0; b < 2; ++b)
    std::printf("aux bearing %zu: swing %.4f s, forward rub %.4f s, backward rub %.4f s (measured %.4f / %.4f / %.4f)\n", b + 1,
                r.rubbing[b].swing_s, r.rubbing[b].forward_s, r.rubbing[b].backward_s, r.measured_rubbing[b].swing_s,
                r.measured_rubbing[b].forward_s, r.measured_rubbing[b].backward_s);
  std::printf("rotor model: %s, %d modes per plane (", r.rotor_modes_per_plane == 2 ? "rigid" : "flexible", r.rotor_modes_per_plane);
  for (size_t i = 0; i < r.structure_trials.size(); ++i)
    std::printf("%scost %.4f with %d", i ? ", " : "", r.structure_trials[i].cost, r.structure_trials[i].modes_per_plane);
  std::printf(")\n");
  std::printf("%d evaluations, %.2f s, %s (%s)\n", r.evaluations, r.wall_s,
              r.converged ? "converged" : (r.bound_active ? "bound active" : "not converged"),
              r.stop_reason.c_str());
  if (!wear_note.empty()) std::printf("%s\n", wear_note.c_str());
  return 0;
}

const amb::host::Registration reg{
    "fit", "fit the multibody drop model to a measured drop (friction coefficient, rubbing states)",
    [](CLI::App& sub, std::function<int()>& run_fn) {
      auto args = std::make_shared<Args>();
      namespace hc = amb::host::cli;
      hc::input_file(sub.add_option("EVENT", args->event, "measured event (.json sidecar of amb-measured-event/1, or its .csv)")->required(),
                     "event");
      hc::input_file(sub.add_option("--board", args->board, "board name or file (default: the event's rig)"), "board");
      sub.add_flag("--force", args->force, "use --board even when it is a board of another rig than the event's");
      hc::positive(sub.add_option("--window", args->window_s, "longest event window compared, s"), 60.0, "s");
      sub.add_flag("--fit-restitution", args->fit_restitution, "also fit the restitution coefficient");
      sub.add_flag("--fit-offset", args->fit_offset, "also fit an offset of the aux-bearing centres");
      sub.add_flag("--fit-law-shape", args->fit_law_shape,
                   "compliant laws: also fit the friction regularisation velocity and the spring exponent");
      sub.add_flag("--lock-in-cost", args->lock_in_cost,
                   "backward-whirl records: compare the whirl after lock-in (speed level, spin-down, force-penetration) instead of lock-in-dependent terms");
      sub.add_flag("--friction-from-fit", args->friction_from_fit,
                   "fit the friction with the model instead of reading it from the contact forces (friction_estimate.hpp)");
      hc::input_file(sub.add_option("--wear-in", args->wear_in, "previous wear record (AMBW) to update"), "wear-record");
      hc::output_path(sub.add_option("--wear-out", args->wear_out, "write the updated wear record here"));
      sub.add_flag("--json", args->json, "print the figures as JSON");
      sub.add_flag("--quiet", args->quiet, "no progress lines on stderr");
      run_fn = [args] { return run(*args); };
    }};

}  // namespace
