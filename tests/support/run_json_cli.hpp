#pragma once
// Run a command line whose stdout must be JSON alone (`--json`): stdout and stderr go to
// files in `dir`, stdout is parsed into `out` (a gtest failure if it is not pure JSON), stderr
// is returned in `err`. Returns the exit code (-1 if the command did not exit normally).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/read_text.hpp"

namespace amb::test {

inline int run_json_cli(const std::string& command, const std::filesystem::path& dir, nlohmann::json& out, std::string& err) {
  const std::filesystem::path o = dir / "stdout", e = dir / "stderr";
  const std::string cmd = command + " > '" + o.string() + "' 2> '" + e.string() + "'";
  const int rc = std::system(cmd.c_str());
  err = read_text(e);
  const std::string text = read_text(o);
  out = nlohmann::json::parse(text, nullptr, false);
  EXPECT_FALSE(out.is_discarded()) << "stdout is not JSON: " << text;
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace amb::test
