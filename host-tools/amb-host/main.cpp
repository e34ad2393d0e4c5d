// amb-host: host tools for AMB drop events (fetch, import, fit, residual, report, ...).
#include <cstdio>
#include <exception>
#include <string>
#include <map>
#include <memory>
#include <vector>

#include "host-tools/amb-host/command.hpp"

#ifndef AMB_HOST_VERSION
#define AMB_HOST_VERSION "0.1.0"  // project version (CMakeLists.txt project())
#endif

namespace amb::host {
namespace {
struct Entry {
  std::string summary;
  CommandSetup setup;
};
std::map<std::string, Entry>& registry() {
  static std::map<std::string, Entry> r;
  return r;
}
}  // namespace

Registration::Registration(std::string name, std::string summary, CommandSetup setup) {
  registry().emplace(std::move(name), Entry{std::move(summary), std::move(setup)});
}
}  // namespace amb::host

int main(int argc, char** argv) {
  CLI::App app{"amb-host: host tools for the AMB supervisor (drop events, fits, wear records)"};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", std::string("amb-host ") + AMB_HOST_VERSION);
  app.footer("Run 'amb-host SUB-COMMAND --help' for the options of one sub-command. Sub-commands that\n"
             "produce figures print them as JSON with --json (stdout); progress goes to stderr.");
  std::map<CLI::App*, std::function<int()>> runs;
  for (auto& [name, entry] : amb::host::registry()) {
    CLI::App* sub = app.add_subcommand(name, entry.summary);
    entry.setup(*sub, runs[sub]);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (app.get_subcommands().empty()) {
    // No sub-command: say what to do instead of a bare parse error.
    std::fprintf(stderr, "%s\namb-host: no sub-command given; choose one of the above, e.g. 'amb-host scenario'\n",
                 app.help().c_str());
    return 1;
  }
  for (auto& [sub, run] : runs) {
    if (sub->parsed() && run) {
      try {
        return run();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "amb-host %s: error: %s\n", sub->get_name().c_str(), e.what());
        return 2;
      }
    }
  }
  return 1;
}
