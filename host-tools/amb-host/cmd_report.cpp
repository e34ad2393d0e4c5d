// amb-host report EVENT: one self-contained HTML page per board event with inline SVG plots
// (orbits, contact angle and rubbing states, speed, forces, load over the circumference, fit
// convergence, residual spectra, wear record). Logic: host-tools/core/report/.
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
#include "host-tools/core/replay/event_board.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "host-tools/core/report/report_builder.hpp"
#include "host-tools/core/report/report_html.hpp"
#include "host-tools/core/ui/progress_bar.hpp"
#include "host-tools/core/wear/wear_record_file.hpp"

namespace {

struct Options {
  std::string event, out, board, wear;
  bool no_replay = false, json = false, progress = false, quiet = false;
};

int bad_input(const std::string& what) {
  std::fprintf(stderr, "amb-host report: error: %s\n", what.c_str());
  return 1;
}

template <class Section>
nlohmann::json section_json(const Section& s) {
  return s.available() ? nlohmann::json{{"available", true}, {"source", s.source}}
                       : nlohmann::json{{"available", false}, {"why_not", s.why_not}};
}

int run(const Options& o) {
  namespace fs = std::filesystem;
  using namespace amb::host;
  amb::fw::EventRecord ev;
  amb::board::BoardConfig board;
  amb::fw::WearRecord wear;
  try {
    ev = replay::read_event_file(o.event);
    board = replay::board_for_event(ev, o.board);
    if (!o.wear.empty()) wear = wear::read_wear_record_file(o.wear);
  } catch (const std::exception& e) {
    return bad_input(e.what());
  }
  const std::string name = fs::path(o.event).filename().string();
  const std::string out = o.out.empty() ? fs::path(o.event).stem().string() + ".html" : o.out;

  report::ReportData d = report::new_report_data("Drop event report: " + name);
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

const amb::host::Registration reg{
    "report", "write one self-contained HTML report (inline SVG plots) for a board event",
    [](CLI::App& sub, std::function<int()>& run_fn) {
      auto o = std::make_shared<Options>();
      namespace hc = amb::host::cli;
      hc::input_file(sub.add_option("EVENT", o->event, "board event file (AMBE v1..v3)")->required(), "ambe");
      hc::output_path(sub.add_option("--out", o->out, "HTML file to write (default: EVENT's name with .html, in the current directory)"));
      hc::input_file(sub.add_option("--board", o->board, "board name or file (default: the board named in the event)"), "board");
      hc::input_file(sub.add_option("--wear", o->wear, "wear record (AMBW) for the wear summary and the cumulative load"), "wear-record");
      sub.add_flag("--no-replay", o->no_replay, "do not replay the event through the firmware");
      sub.add_flag("--json", o->json, "print the report path and its sections as JSON on stdout");
      sub.add_flag("--progress", o->progress, "show a progress bar on stderr even when it is not a terminal");
      sub.add_flag("--quiet", o->quiet, "no progress bar, not even on a terminal")->excludes("--progress");
      run_fn = [o] { return run(*o); };
    }};

}  // namespace
