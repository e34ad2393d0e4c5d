// amb-host: host tools for AMB drop events (fetch, import, fit, residual, report, ...).
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <vector>

#include "host-tools/amb-host/command.hpp"

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
  app.require_subcommand(1);
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
