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

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/events/event_board_choice.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/residual/candidate_report.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/engine/elements.hpp"
#include "host-tools/core/residual/journal_residual.hpp"
#include "host-tools/core/residual/learned_correction.hpp"
#include "host-tools/core/residual/residual_json.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"
#include "host-tools/core/residual/sweep_report.hpp"
#include "host-tools/core/sweep/sweep_analysis.hpp"
#include "host-tools/core/sweep/sweep_event.hpp"
#include "host-tools/core/ui/progress_lines.hpp"

namespace {

namespace hr = amb::host::residual;

struct Args {
  std::string event;
  std::string board;
  bool json = false;
  bool contact_law_update = false;
  bool learned_correction = false;  // after the loop: a learned map, reported apart from the named elements
  std::string plot;  // sweep: FRF overlay SVG path
  bool quiet = false;  // no progress lines on stderr
  bool force = false;  // accept a board of another rig than the event's
};

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
  if (!a.quiet) std::fprintf(stderr, "drop event: levitated part through the steady loop, drop part through the drop model fit\n");
  hr::DropResidualOptions dro;
  dro.update_contact_law = a.contact_law_update;
  if (!a.quiet) dro.progress = amb::host::ui::periodic_lines("residual");
  const auto o = hr::run_drop_residual(rec, b, dro);
  if (a.json) {
    nlohmann::json j = hr::drop_residual_json(o);
    if (a.learned_correction) j["learned_correction"] = hr::learned_correction_json(drop_levitated_correction(rec, b, o));
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::fputs(hr::residual_text(o.verdict, o.before, o.after, hr::drop_ranking(o), o.effects_added, hr::drop_notes(o)).c_str(), stdout);
    if (a.learned_correction) std::fputs(hr::learned_correction_text(drop_levitated_correction(rec, b, o)).c_str(), stdout);
  }
  return 0;
}

// A board's sweep event (AMBE v4, issue 35): the loop-sensitivity sweep's residual loop on
// the board's model (the analysis amb-host sweep runs; --board picks the model's board).
int run_board_sweep(const Args& a) {
  const auto rec = amb::host::sweep::read_sweep_event_file(a.event);
  const amb::board::BoardConfig b = amb::board::load_board(a.board.empty() ? rec.board_name : a.board);
  if (!a.quiet) std::fprintf(stderr, "residual: loop sweep of %s, %zu axes, on the model of %s\n", rec.board_name.c_str(), rec.axes.size(), b.name.c_str());
  const auto an = amb::host::sweep::analyse_sweep(rec, b);
  if (a.json) {
    std::printf("%s\n", amb::host::sweep::sweep_analysis_json(an).dump(2).c_str());
  } else {
    const auto& o = an.residual;
    std::printf("verdict: %s\n", o.verdict.c_str());
    std::printf("error before -> after: S %.2f -> %.2f dB rms, G %.2f -> %.2f dB rms\n", o.before.s_db_rms, o.after.s_db_rms,
                o.before.g_db_rms, o.after.g_db_rms);
    for (const auto& e : o.effects_added) std::printf("added: %s\n", e.name.c_str());
    for (const std::string& n : an.notes) std::printf("note: %s\n", n.c_str());
  }
  return 0;
}

int run_steady(const Args& a) {
  const amb::host::LoadedEvent rec = amb::host::load_event(a.event);
  for (const auto& w : rec.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  // The event's own rig, or --board of the same rig (another rig's board is refused unless --force).
  const auto b = amb::host::board_for_loaded_event(rec, a.board, a.force);
  if (!a.plot.empty()) std::fprintf(stderr, "warning: --plot is for sweeps; %s is not one (no plot written)\n", rec.source.c_str());
  if (hr::is_drop_event(rec, b)) return run_drop(a, rec, b);
  if (hr::is_journal_event(rec, b)) {  // journal-bearing record (seed 002): journal_bearing_wear
    const auto o = hr::run_journal_residual(rec, b);
    if (a.learned_correction) std::fprintf(stderr, "--learned-correction: not available for journal-bearing records (skipped)\n");
    std::printf("%s\n", a.json ? hr::journal_residual_json(o).c_str() : hr::journal_residual_text(o).c_str());
    return 0;
  }
  if (!a.quiet) std::fprintf(stderr, "residual: steady run, %s\n", rec.source.c_str());
  const auto d = hr::extract_steady(rec, b);
  const auto o = hr::run_residual_loop(d, b);
  // After the loop has decided: the learned correction reads its final model and changes nothing.
  hr::LearnedCorrectionSummary lc;
  if (a.learned_correction) lc = hr::learned_correction_steady(d, o.after);
  if (a.json) {
    nlohmann::json j = hr::steady_residual_json(d, o);
    if (a.learned_correction) j["learned_correction"] = hr::learned_correction_json(lc);
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::fputs(hr::residual_text(o.verdict, o.before.error, o.after.error, o.ranking, o.effects_added, o.structure.notes).c_str(), stdout);
    if (a.learned_correction) std::fputs(hr::learned_correction_text(lc).c_str(), stdout);
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
    nlohmann::json j = hr::sweep_residual_json(o);
    if (a.learned_correction) j["learned_correction"] = hr::learned_correction_json(hr::learned_correction_sweep(o));
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::fputs(hr::residual_text(o.verdict, o.before.error, o.after.error, o.ranking, o.effects_added, o.notes).c_str(), stdout);
    if (a.learned_correction) std::fputs(hr::learned_correction_text(hr::learned_correction_sweep(o)).c_str(), stdout);
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
      amb::host::cli::output_file(
          sub.add_option("--plot", a->plot, "sweep only: write the measured vs modelled FRF overlay (SVG) to this file"));
      sub.add_flag("--quiet", a->quiet, "no progress lines on stderr");
      sub.add_flag("--force", a->force, "accept a --board of another rig than the event's (normally refused)");
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
          if (amb::host::sweep::is_sweep_event_file(a->event)) return run_board_sweep(*a);
          return run_steady(*a);
        } catch (const amb::host::EventLoadError& e) {  // bad input: the file is named
          std::fprintf(stderr, "amb-host residual: error: %s\n", e.what());
          return 1;
        } catch (const amb::board::BoardError& e) {  // bad input: the board file and key are named
          std::fprintf(stderr, "amb-host residual: error: %s\n", e.what());
          return 1;
        } catch (const std::invalid_argument& e) {  // bad input: the option or another rig's board is named
          std::fprintf(stderr, "amb-host residual: error: %s\n", e.what());
          return 1;
        } catch (const std::exception& e) {  // the work itself failed (e.g. a record the loop cannot read as a drop)
          std::fprintf(stderr, "amb-host residual: error: %s\n", e.what());
          return 2;
        }
      };
    }};

}  // namespace
