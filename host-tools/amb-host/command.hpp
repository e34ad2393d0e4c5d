#pragma once
// Sub-command registry of amb-host. Each sub-command lives in its own cmd_<name>.cpp and
// registers itself with a file-scope `const amb::host::Registration reg{...}`.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace amb::host {

/// Adds the sub-command's options to `sub`; stores the code to run in `run`, which returns
/// the process exit code (0 success, 1 bad input, 2 failure of the work itself).
using CommandSetup = std::function<void(CLI::App& sub, std::function<int()>& run)>;

struct Registration {
  Registration(std::string name, std::string summary, CommandSetup setup);
};

}  // namespace amb::host
