// amb-host report EVENT: one self-contained HTML page per event (a board event, AMBE, or a
// measured event, amb-measured-event/1) with inline SVG plots (orbits, contact angle and
// rubbing states, speed, forces, load over the circumference, fit convergence, residual
// spectra, wear record). --fit runs the Phase C fit on the event (as amb-host fit does) and
// adds its convergence, forces and load. Logic: host-tools/core/report/.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware/wear/wear_record.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/events/board_event_file.hpp"
#include "host-tools/core/events/event_board_choice.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/fit/drop_measurement.hpp"
#include "host-tools/core/replay/event_board.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "host-tools/core/report/report_builder.hpp"
#include "host-tools/core/report/report_html.hpp"
#include "host-tools/core/report/report_measured.hpp"
#include "host-tools/core/ui/progress_bar.hpp"
#include "host-tools/core/wear/wear_record_file.hpp"
#include "host-tools/core/ui/progress_lines.hpp"

namespace {

struct Options {
  std::string event, out, board, wear;
  bool no_replay = false, json = false, progress = false, quiet = false, fit = false, force = false;
  double window_s = 0.4;
};

int bad_input(const std::string& what) {
  std::fprintf(stderr, "amb-host report: error: %s\n", what.c_str());
  return 1;
}

std::string fmt_window(double window_s) {
  char b[64];
  std::snprintf(b, sizeof b, " (window %.3g s, as amb-host fit --window)", window_s);
  return b;
}

template <class Section>
nlohmann::json section_json(const Section& s) {
  return s.available() ? nlohmann::json{{"available", true}, {"source", s.source}}
                       : nlohmann::json{{"available", false}, {"why_not", s.why_not}};
}

int run(const Options& o) {
  namespace fs = std::filesystem;
  using namespace amb::host;
  // A board event (AMBE) keeps its firmware record (replay, quick-look); a measured event is
  // read through the common loader. Everything is read before any work starts.
  const bool board_event = is_board_event_file(o.event);
  amb::fw::EventRecord ev;
  LoadedEvent loaded;
  amb::board::BoardConfig board;
  amb::fw::WearRecord wear;
  try {
    if (board_event) {
      ev = replay::read_event_file(o.event);
      board = replay::board_for_event(ev, o.board);
      if (o.fit) loaded = to_loaded_event(ev, o.event);
    } else {
      loaded = load_event(o.event);
      board = board_for_loaded_event(loaded, o.board, o.force);
    }
    if (!o.wear.empty()) wear = wear::read_wear_record_file(o.wear);
  } catch (const std::exception& e) {
    return bad_input(e.what());
  }
  fit::DropFitOptions fo;
  fit::DropMeasurement measurement;
  if (o.fit) {
    fo.max_window_s = o.window_s;
    if (!o.quiet) fo.progress = ui::periodic_lines("report");
    if (const std::string e = fo.check(); !e.empty()) return bad_input(cli::in_option_names(e, {{"max_window_s", "--window"}}));
    try {
      measurement = fit::drop_measurement_from_event(loaded);
    } catch (const std::exception& e) {
      return bad_input(e.what());
    }
  }
  const std::string name = fs::path(o.event).filename().string();
  const std::string out = o.out.empty() ? fs::path(o.event).stem().string() + ".html" : o.out;

  report::ReportData d = report::new_report_data((board_event ? "Drop event report: " : "Measured event report: ") + name);
  if (board_event) {
    report::add_event(d, ev, board, name);
    if (!o.no_replay) {
      std::optional<ui::ProgressBar> bar;
      if (!o.quiet) bar.emplace("replay " + name, o.progress);
      replay::ReplayOptions ro;
      if (bar) ro.progress = [&bar](double f) { bar->update(f); };
      const replay::ReplayResult r = replay::replay_event(ev, board, ro);
      if (bar) bar->finish();
      report::add_replay(d, r);
    }
  } else {
    report::add_loaded_event(d, loaded, board, name);
  }
  if (o.fit) {
    fit::DropFitResult r;
    try {
      r = fit::fit_drop(measurement, board, fo);
    } catch (const std::invalid_argument& e) {
      return bad_input(e.what());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "amb-host report: fit failed: %s\n", e.what());
      return 2;
    }
    report::add_fit(d, r, "amb-host report --fit: the Phase C fit of " + name + fmt_window(o.window_s));
  }
  if (!o.wear.empty()) report::add_wear_record(d, wear, fs::path(o.wear).filename().string());
  const std::string written = report::write_event_report(d, out);

  if (o.json) {
    nlohmann::json j;
    j["report"] = written;
    j["event"] = o.event;
    j["plots"] = report::plot_ids(d);
    j["sections"] = {{"orbit", section_json(d.orbit)}, {"rubbing", section_json(d.rubbing)},
                     {"speed", section_json(d.speed)}, {"forces", section_json(d.forces)},
                     {"load", section_json(d.load)},   {"fit", section_json(d.fit)},
                     {"residual", section_json(d.residual)}, {"drop_residual", section_json(d.drop_residual)},
                     {"wear", section_json(d.wear)},
                     {"replay", section_json(d.replay)}};
    if (d.replay.available()) j["replay_reproduced"] = d.replay.data->reproduced;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%s\n", written.c_str());
    for (const auto& id : report::unavailable_ids(d)) std::fprintf(stderr, "  note: section %s not available\n", id.c_str());
  }
  return 0;
}

void declare(CLI::App& sub, Options& o) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("EVENT", o.event, "board event file (AMBE v1..v3), or measured event (.json/.csv/stem of amb-measured-event/1)")->required(), "event");
  hc::output_file(sub.add_option("--out", o.out, "HTML file to write (default: EVENT's name with .html, in the current directory)"));
  hc::input_file(sub.add_option("--board", o.board, "board name or file (default: the board named in the event, or its rig's)"), "board");
  hc::input_file(sub.add_option("--wear", o.wear, "wear record (AMBW) for the wear summary and the cumulative load"), "wear-record");
  sub.add_flag("--no-replay", o.no_replay, "do not replay the event through the firmware (board events; a measured event has nothing to replay)");
  sub.add_flag("--fit", o.fit, "fit the drop model to the event (Phase C, as amb-host fit) and show the fit, contact forces and load");
  hc::positive(sub.add_option("--window", o.window_s, "with --fit: longest event window compared, s"), 60.0, "s");
  sub.add_flag("--force", o.force, "use --board even when it is a board of another rig than the event's (measured events)");
  sub.add_flag("--json", o.json, "print the report path and its sections as JSON on stdout");
  sub.add_flag("--progress", o.progress, "show a progress bar on stderr even when it is not a terminal");
  sub.add_flag("--quiet", o.quiet, "no progress bar, not even on a terminal")->excludes("--progress");
}

const amb::host::Registration reg = amb::host::make_command<Options>(
    "report", "write one self-contained HTML report (inline SVG plots) for a board or measured event", declare, run);

}  // namespace
