#pragma once
// Runs one command line of a built executable for the CLI tests: argv quoted for the shell,
// in a working folder, under `timeout` (a hang is a failure, not a stuck test), stdout and
// stderr captured.
#include <filesystem>
#include <string>
#include <vector>

namespace amb::test {

struct CliRun {
  int exit_code = -1;   ///< the process's exit code; 124 when the timeout killed it
  bool timed_out = false;
  std::string out, err;
  double wall_s = 0.0;
};

/// Runs `exe args...` in `cwd` with a limit of `timeout_s` seconds.
CliRun run_cli(const std::string& exe, const std::vector<std::string>& args, const std::filesystem::path& cwd,
               double timeout_s = 20.0);

/// The command line as a person would type it (for failure messages).
std::string shown(const std::vector<std::string>& args);

}  // namespace amb::test
