#include "tests/cli/cli_run.hpp"

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>

#include "tests/support/read_text.hpp"

namespace amb::test {

namespace {
std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

std::string shown(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += (s.empty() ? "" : " ") + (a.empty() || a.find_first_of(" '\"") != std::string::npos ? quote(a) : a);
  return s;
}

CliRun run_cli(const std::string& exe, const std::vector<std::string>& args, const std::filesystem::path& cwd,
               double timeout_s) {
  namespace fs = std::filesystem;
  const fs::path o = cwd.parent_path() / (cwd.filename().string() + ".stdout");
  const fs::path e = cwd.parent_path() / (cwd.filename().string() + ".stderr");
  std::string cmd = "cd " + quote(cwd.string()) + " && timeout -k 2 " + std::to_string(timeout_s) + " " + quote(exe);
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " > " + quote(o.string()) + " 2> " + quote(e.string()) + " < /dev/null";
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = std::system(cmd.c_str());
  CliRun r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.exit_code = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.timed_out = r.exit_code == 124 || r.exit_code == 137;
  r.out = read_text(o);
  r.err = read_text(e);
  std::error_code ec;
  fs::remove(o, ec);
  fs::remove(e, ec);
  return r;
}

}  // namespace amb::test
