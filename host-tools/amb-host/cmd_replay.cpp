// amb-host replay EVENT: run the firmware over a recorded event on the replay HAL backend and
// check that it reproduces the recorded outputs, triggers and Phase B result bit for bit.
#include <cstdio>
#include <exception>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/replay/event_board.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "host-tools/core/replay/replay_json.hpp"
#include "host-tools/core/ui/progress_bar.hpp"

namespace {

struct Options {
  std::string event;
  std::string board;
  bool json = false;
  bool progress = false;
  bool quiet = false;
  size_t max_differences = 20;
};

int run(const Options& o) {
  using namespace amb::host::replay;
  amb::fw::EventRecord ev;
  amb::board::BoardConfig board;
  try {
    ev = read_event_file(o.event);
    board = board_for_event(ev, o.board);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host replay: error: %s\n", e.what());
    return 1;
  }
  std::optional<amb::host::ui::ProgressBar> bar;
  if (!o.quiet) bar.emplace("replay " + o.event, o.progress);
  ReplayOptions ro;
  ro.max_listed_differences = o.max_differences;
  if (bar) ro.progress = [&bar](double f) { bar->update(f); };
  const ReplayResult r = replay_event(ev, board, ro);
  if (bar) bar->finish(std::to_string(ev.samples.size()) + " samples");

  // Success: everything that is claimed reproducible was reproduced.
  const bool outputs_ok = r.mode == "not_reproducible" || r.comparison.bit_exact;
  const bool ok = outputs_ok && r.trigger.reproduced && r.diagnosis.type_reproduced;
  if (o.json) {
    nlohmann::json j = to_json(r);
    j["event"] = o.event;
    j["ok"] = ok;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("Replay of %s on %s (%zu samples, trigger at sample %zu)\n", o.event.c_str(), r.board.c_str(),
                ev.samples.size(), static_cast<size_t>(ev.meta.trigger_index));
    std::printf("  start   : %s; warm-up %s (%llu periods: %s)\n", r.mode.c_str(), r.warm_up.reached ? "reached" : "NOT reached",
                static_cast<unsigned long long>(r.warm_up.steps), r.warm_up.note.c_str());
    std::printf("  why     : %s\n", r.compare_from_reason.c_str());
    std::printf("%s", format_comparison(r.comparison).c_str());
    std::printf("  trigger : recorded sample %zu (%s), replayed %s -> %s\n", r.trigger.recorded_index,
                r.trigger.recorded_cause.c_str(),
                r.trigger.replayed_frozen ? ("sample " + std::to_string(r.trigger.replayed_index) + " (" + r.trigger.replayed_cause + ")").c_str()
                                          : "no window frozen",
                r.trigger.reproduced ? "reproduced" : "DIFFERENT");
    std::printf("  Phase B : recorded %s%s, replayed %s -> %s\n", amb::fw::diag::to_string(r.diagnosis.recorded.type),
                r.diagnosis.recorded_available ? "" : " (re-run: not in the event)",
                amb::fw::diag::to_string(r.diagnosis.replayed.type),
                r.diagnosis.bit_exact ? "bit-exact" : (r.diagnosis.type_reproduced ? "same type, fields differ (" + r.diagnosis.first_difference + ")" : std::string("DIFFERENT")).c_str());
    std::printf("  verdict : %s\n", ok ? "reproduced" : "NOT reproduced (see the differences above)");
  }
  return ok ? 0 : 2;
}

void declare(CLI::App& sub, Options& o) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("EVENT", o.event, "board event file (AMBE v1..v3, e.g. event_00000001.ambe)")->required(), "ambe");
  hc::input_file(sub.add_option("--board", o.board, "board name or file to replay with (default: the board named in the event)"),
                 "board");
  hc::whole(sub.add_option("--max-differences", o.max_differences, "differences listed at most"), 0, 100000);
  sub.add_flag("--json", o.json, "print the result as JSON on stdout");
  sub.add_flag("--progress", o.progress, "show a progress bar on stderr even when it is not a terminal");
  sub.add_flag("--quiet", o.quiet, "no progress bar, not even on a terminal")->excludes("--progress");
  sub.footer("Exit status: 0 reproduced, 1 bad input, 2 not reproduced.");
}

const amb::host::Registration reg = amb::host::make_command<Options>(
    "replay", "replay a recorded event through the firmware (replay HAL) and check it bit for bit", declare, run);

}  // namespace
