// amb-host export EVENT --out STEM [--json]: convert an event (normally a board AMBE file) to
// the measured-event exchange format STEM.csv + STEM.json. Logic:
// host-tools/core/events/measured_event.hpp.
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/amb-host/event_input.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"

namespace {

struct Args {
  std::string event;
  std::string out;
  bool json = false;
};

int run(const Args& a) {
  const std::optional<amb::host::LoadedEvent> loaded = amb::host::load_event_or_report(a.event, "export");
  if (!loaded) return 1;
  const amb::host::LoadedEvent& e = *loaded;
  amb::host::export_measured_event(e, a.out);
  const auto paths = amb::host::measured_event_paths(a.out);
  if (a.json) {
    nlohmann::json j;
    j["json"] = paths.json;
    j["csv"] = paths.csv;
    j["samples"] = e.samples();
    j["sample_rate_hz"] = e.sample_rate_hz;
    j["trigger_index"] = e.trigger_index;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("wrote %s and %s (%zu samples at %.1f Hz, trigger at %zu)\n", paths.json.c_str(), paths.csv.c_str(),
                e.samples(), e.sample_rate_hz, e.trigger_index);
  }
  return 0;
}

void declare(CLI::App& sub, Args& args) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("EVENT", args.event, "board event file (or a measured event)")->required(), "event");
  hc::output_file(sub.add_option("--out", args.out, "output stem: writes STEM.csv and STEM.json")->required());
  sub.add_flag("--json", args.json, "print what was written as JSON");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "export", "Convert an event (board AMBE file) to the measured-event exchange format (CSV + JSON)", declare, run);

}  // namespace
