#pragma once
// Sub-command registry of amb-host. Each sub-command lives in its own cmd_<name>.cpp and
// registers itself with a file-scope `const amb::host::Registration reg = make_command<Args>(...)`
// (an options struct, a function that declares the options into it, a function that runs), or
// with `Registration reg{name, summary, setup}` when it has sub-commands of its own.
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

namespace amb::host {

/// Adds the sub-command's options to `sub`; stores the code to run in `run`, which returns
/// the process exit code (0 success, 1 bad input, 2 failure of the work itself).
using CommandSetup = std::function<void(CLI::App& sub, std::function<int()>& run)>;

struct Registration {
  Registration(std::string name, std::string summary, CommandSetup setup);
};

/// The usual sub-command: `Args` holds its options, `declare(sub, args)` adds them to `sub`
/// bound to `args`, `run(args)` does the work after parsing and returns the exit code.
/// `const Registration reg = make_command<Args>("name", "summary", declare, run);`
template <class Args, class Declare, class Run>
Registration make_command(std::string name, std::string summary, Declare declare, Run run) {
  return Registration(std::move(name), std::move(summary), [declare, run](CLI::App& sub, std::function<int()>& runner) {
    auto args = std::make_shared<Args>();
    declare(sub, *args);
    runner = [args, run] { return run(*args); };
  });
}

}  // namespace amb::host
