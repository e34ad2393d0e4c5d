// amb-host import FILE [--json]: read and validate a board event file (AMBE) or a measured
// event (amb-measured-event/1 sidecar + CSV), and summarise it. Logic:
// host-tools/core/events/load_event.hpp.
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/amb-host/event_input.hpp"
#include "host-tools/core/events/event_json.hpp"
#include "host-tools/core/events/load_event.hpp"

namespace {

struct Args {
  std::string file;
  bool json = false;
};

int run(const Args& a) {
  const std::optional<amb::host::LoadedEvent> loaded = amb::host::load_event_or_report(a.file, "import");
  if (!loaded) return 1;
  const amb::host::LoadedEvent& e = *loaded;
  if (a.json) {
    std::printf("%s\n", amb::host::event_summary_json(e).dump(2).c_str());
    return 0;
  }
  std::printf("%s: %s, rig %s (board %s)\n", e.source.c_str(), e.format.c_str(), e.rig.c_str(), e.board.c_str());
  std::printf("  %zu samples at %.1f Hz (%.3f s), trigger at sample %zu", e.samples(), e.sample_rate_hz,
              static_cast<double>(e.samples()) / e.sample_rate_hz, e.trigger_index);
  if (!e.trigger_cause.empty()) std::printf(" (%s)", e.trigger_cause.c_str());
  if (e.speed_at_trigger_hz) std::printf(", speed %.2f Hz (%.0f rpm)", *e.speed_at_trigger_hz, *e.speed_at_trigger_hz * 60.0);
  std::printf("\n");
  auto list = [](const char* what, const std::vector<amb::host::LoadedChannel>& v) {
    for (const auto& c : v)
      std::printf("  %-14s %-8s axial %.4f m, angle %6.1f deg -> %s%s\n", what, c.name.c_str(), c.axial_m, c.angle_deg,
                  c.rig_index >= 0 ? ("rig element " + std::to_string(c.rig_index)).c_str() : "unmatched",
                  c.inverted ? " (inverted)" : "");
  };
  list("displacement", e.displacement);
  list("current", e.current);
  list("other", e.other);
  if (!e.declared_faults.empty()) {
    std::printf("  declared faults:");
    for (const auto& f : e.declared_faults) std::printf(" %s", f.c_str());
    std::printf("\n");
  }
  if (e.phase_b)
    std::printf("  Phase B: %s (confidence %.2f): %s\n", amb::fw::diag::to_string(e.phase_b->type), e.phase_b->confidence,
                e.phase_b->summary.c_str());
  for (const auto& w : e.warnings) std::printf("  warning: %s\n", w.c_str());
  return 0;
}

void declare(CLI::App& sub, Args& args) {
  amb::host::cli::input_file(sub.add_option("FILE", args.file, "board event file, or measured event .json/.csv/stem")->required(),
                             "event");
  sub.add_flag("--json", args.json, "print the summary as JSON");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "import", "Read and validate an event (board AMBE file or amb-measured-event/1 JSON+CSV)", declare, run);

}  // namespace
