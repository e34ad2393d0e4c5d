// amb-host: host tools for AMB drop events (fetch, import, fit, residual, report, ...).
// The one dispatcher of the command-line contract (command.hpp): exit 0 success, 1 bad input,
// 2 failure of the work itself, whatever the sub-command or CLI11 says.
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/amb-host/command_table.hpp"
#include "host-tools/core/events/loaded_event.hpp"

#ifndef AMB_VERSION
#error "AMB_VERSION is set from project(VERSION) in host-tools/CMakeLists.txt"
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

/// The deepest sub-command given on the command line ("hybrid train"), for messages.
std::string given_path(const CLI::App& app) {
  std::string path;
  const CLI::App* a = &app;
  while (true) {
    const auto subs = a->get_subcommands();
    if (subs.empty()) break;
    a = subs.front();
    path += (path.empty() ? "" : " ") + a->get_name();
  }
  return path;
}
}  // namespace

Registration::Registration(std::string name, std::string summary, CommandSetup setup) {
  registry().emplace(std::move(name), Entry{std::move(summary), std::move(setup)});
}
}  // namespace amb::host

int main(int argc, char** argv) {
  CLI::App app{"amb-host: host tools for the AMB supervisor (drop events, fits, wear records)"};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", std::string("amb-host ") + AMB_VERSION);
  bool table = false, man = false;
  app.add_flag("--command-table", table, "print the command table as JSON (for tests and tools)")->group("");
  app.add_flag("--man", man, "print the man page generated from the command table")->group("");
  app.footer("Run 'amb-host SUB-COMMAND --help' for the options of one sub-command. Sub-commands that\n"
             "produce figures print them as JSON with --json (stdout); progress goes to stderr.\n"
             "Exit status: 0 success, 1 bad input (the option or file is named), 2 the work itself failed.");
  std::map<CLI::App*, std::function<int()>> runs;
  for (auto& [name, entry] : amb::host::registry()) {
    CLI::App* sub = app.add_subcommand(name, entry.summary);
    entry.setup(*sub, runs[sub]);
  }
  amb::host::add_examples_to_help(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version: CLI11 prints them, success. Every other CLI11 error (its own codes
    // 104..109: missing option, conversion, validation, ...) is bad input: exit 1.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    const std::string path = amb::host::given_path(app);
    std::string what = e.what();
    if (dynamic_cast<const CLI::RequiredError*>(&e) && what.find("ubcommand") != std::string::npos) {
      // Say which sub-commands there are.
      const CLI::App* at = &app;
      while (!at->get_subcommands().empty()) at = at->get_subcommands().front();
      std::string names;
      for (const CLI::App* s : at->get_subcommands([](const CLI::App*) { return true; }))
        names += (names.empty() ? "" : ", ") + s->get_name();
      what += " (one of: " + names + ")";
    }
    std::fprintf(stderr, "amb-host%s%s: error: %s\n", path.empty() ? "" : " ", path.c_str(), what.c_str());
    std::fprintf(stderr, "Run 'amb-host %s%s--help' for the options.\n", path.c_str(), path.empty() ? "" : " ");
    return 1;
  }
  if (table) {
    std::printf("%s\n", amb::host::command_table(app, AMB_VERSION).dump(1).c_str());
    return 0;
  }
  if (man) {
    std::printf("%s", amb::host::man_page(app, AMB_VERSION).c_str());
    return 0;
  }
  if (app.get_subcommands().empty()) {
    // No sub-command: say what to do instead of a bare parse error.
    std::fprintf(stderr, "%s\namb-host: no sub-command given; choose one of the above, e.g. 'amb-host scenario'\n",
                 app.help().c_str());
    return 1;
  }
  for (auto& [sub, run] : runs) {
    if (!sub->parsed() || !run) continue;
    const char* name = sub->get_name().c_str();
    // Bad input found while working (a loader refusing a file, a value the model cannot take):
    // 1. Anything else thrown: the work failed, 2.
    try {
      return run();
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "amb-host %s: error: %s\n", name, e.what());
      return 1;
    } catch (const amb::host::EventLoadError& e) {
      std::fprintf(stderr, "amb-host %s: error: %s\n", name, e.what());
      return 1;
    } catch (const amb::board::BoardError& e) {
      std::fprintf(stderr, "amb-host %s: error: %s\n", name, e.what());
      return 1;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "amb-host %s: error: out of memory (an input asks for more than this machine has)\n", name);
      return 2;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "amb-host %s: error: %s\n", name, e.what());
      return 2;
    }
  }
  return 1;
}
