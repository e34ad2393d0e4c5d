// amb-host fit EVENT: Phase C of seed 000: fit the multibody drop model to a measured drop
// (measured-event format) by implicit filtering; optionally fold the fitted event into a
// wear record (Phase D/E). Logic: host-tools/core/fit/, host-tools/core/wear/.
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

#include "firmware/board/board.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/fit/fit_result_json.hpp"
#include "host-tools/core/events/event_board_choice.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "host-tools/core/ui/progress_lines.hpp"
#include "host-tools/core/wear/wear_record_file.hpp"
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
  if (!a.wear_out.empty())
    if (const std::string e = hw::wear_record_path_problem(a.wear_out); !e.empty()) return bad_input("--wear-out " + e);
  if (!a.wear_in.empty()) {
    try {
      prev = hw::read_wear_record_file(a.wear_in, board.name);
    } catch (const std::invalid_argument& e) {
      return bad_input(std::string("--wear-in: ") + e.what());
    }
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
    amb::fw::WearRecord next;
    try {
      next = hw::account_drop(prev, r.trace.contact_steps, r.rubbing, r.friction_coefficient, board.name,
                              hw::wall_clock_unix_s(), hw::WearOptions{})
                 .record;
    } catch (const std::invalid_argument& e) {
      return bad_input(e.what());
    }
    try {
      hw::write_wear_record_file(a.wear_out, next);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "amb-host fit: error: --wear-out: %s\n", e.what());
      return 2;
    }
    wear_note = "wear record sequence " + std::to_string(next.sequence) + " written to " + a.wear_out;
  }

  if (a.json) {
    std::printf("%s\n", hf::fit_result_json({board.name, a.event, wear_note, r}).dump(2).c_str());
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

void declare(CLI::App& sub, Args& args) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("EVENT", args.event, "measured event (.json sidecar of amb-measured-event/1, or its .csv)")->required(),
                 "event");
  hc::input_file(sub.add_option("--board", args.board, "board name or file (default: the event's rig)"), "board");
  sub.add_flag("--force", args.force, "use --board even when it is a board of another rig than the event's");
  hc::positive(sub.add_option("--window", args.window_s, "longest event window compared, s"), 60.0, "s");
  sub.add_flag("--fit-restitution", args.fit_restitution, "also fit the restitution coefficient");
  sub.add_flag("--fit-offset", args.fit_offset, "also fit an offset of the aux-bearing centres");
  sub.add_flag("--fit-law-shape", args.fit_law_shape,
               "compliant laws: also fit the friction regularisation velocity and the spring exponent");
  sub.add_flag("--lock-in-cost", args.lock_in_cost,
               "backward-whirl records: compare the whirl after lock-in (speed level, spin-down, force-penetration) instead of lock-in-dependent terms");
  sub.add_flag("--friction-from-fit", args.friction_from_fit,
               "fit the friction with the model instead of reading it from the contact forces (friction_estimate.hpp)");
  hc::input_file(sub.add_option("--wear-in", args.wear_in, "previous wear record (AMBW) to update"), "wear-record");
  hc::output_path(sub.add_option("--wear-out", args.wear_out, "write the updated wear record here"));
  sub.add_flag("--json", args.json, "print the figures as JSON");
  sub.add_flag("--quiet", args.quiet, "no progress lines on stderr");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "fit", "fit the multibody drop model to a measured drop (friction coefficient, rubbing states)", declare, run);

}  // namespace
