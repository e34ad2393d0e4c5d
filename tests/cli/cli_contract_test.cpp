// The rest of the command-line contract (issue 36): --version from project(VERSION) on every
// executable, an example in every sub-command's help (and in the table), the man page equal
// to what the command table generates and listing every sub-command, and the firmware
// executables' numbers checked like amb-host's.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/cli/cli_run.hpp"
#include "tests/support/read_text.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using amb::test::CliRun;

fs::path work(const std::string& name) {
  const fs::path d = fs::path(amb::test::artefact_dir()) / "cli_contract" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

nlohmann::json table() {
  const CliRun r = amb::test::run_cli(AMB_HOST_EXE, {"--command-table"}, work("table"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

std::vector<std::string> exes() {
  std::vector<std::string> e = {AMB_HOST_EXE, AMB_FIRMWARE_EXE};
#ifdef AMB_PLANT_EXE
  e.push_back(AMB_PLANT_EXE);
#endif
  return e;
}

TEST(CliContract, EveryExecutablePrintsTheProjectVersion) {
  for (const std::string& exe : exes()) {
    const CliRun r = amb::test::run_cli(exe, {"--version"}, work("version"));
    EXPECT_EQ(r.exit_code, 0) << exe << ": " << r.err;
    const std::string name = fs::path(exe).filename().string();
    EXPECT_EQ(r.out, name + " " + AMB_PROJECT_VERSION + "\n") << exe;
  }
}

TEST(CliContract, EverySubCommandHasAnExampleInItsHelpUsingItsOwnOptions) {
  const nlohmann::json t = table();
  ASSERT_GE(t["commands"].size(), 20u);
  for (const auto& cmd : t["commands"]) {
    const std::string path = cmd["path"], ex = cmd["example"];
    ASSERT_FALSE(ex.empty()) << path << " has no example (host-tools/amb-host/command_table.cpp)";
    std::vector<std::string> args;
    std::string w;
    for (char c : path + " ") {
      if (c == ' ') {
        args.push_back(w);
        w.clear();
      } else {
        w += c;
      }
    }
    // The example runs this sub-command (a parent's example may run one of its children).
    EXPECT_EQ(ex.rfind("amb-host " + args.front(), 0), 0u) << path << ": " << ex;
    // Every --option in a leaf's example is one of its options (or its parent's).
    if (!cmd["has_subcommands"].get<bool>()) {
      std::set<std::string> known;
      for (const auto& c2 : t["commands"])
        if (path.rfind(c2["path"].get<std::string>(), 0) == 0)
          for (const auto& o : c2["options"]) known.insert(o["name"].get<std::string>());
      size_t p = 0;
      while ((p = ex.find(" --", p)) != std::string::npos) {
        const size_t e = ex.find(' ', p + 1);
        const std::string opt = ex.substr(p + 1, e == std::string::npos ? std::string::npos : e - p - 1);
        EXPECT_TRUE(known.count(opt)) << path << ": the example uses " << opt << ", which the command does not have";
        p += 3;
      }
    }
    args.push_back("--help");
    const CliRun r = amb::test::run_cli(AMB_HOST_EXE, args, work("help"));
    EXPECT_EQ(r.exit_code, 0) << path << ": " << r.err;
    EXPECT_NE(r.out.find("Example:\n  " + ex), std::string::npos) << path << " --help:\n" << r.out;
    EXPECT_NE(r.out.find("Exit status: 0 "), std::string::npos) << path;
    EXPECT_NE(r.out.find("1 bad input"), std::string::npos) << path;
  }
}

TEST(CliContract, DefaultsAreStatedInTheHelp) {
  // Spot checks of defaults CLI11 prints from the variables (not from hand-written text).
  const CliRun r = amb::test::run_cli(AMB_HOST_EXE, {"wear-id", "--help"}, work("defaults"));
  EXPECT_NE(r.out.find("=3p"), std::string::npos) << r.out;  // the default wear model
  const CliRun b = amb::test::run_cli(AMB_HOST_EXE, {"bearing-check", "--help"}, work("defaults"));
  EXPECT_NE(b.out.find("6205"), std::string::npos) << b.out;  // the bearing catalogue is listed
}

TEST(CliContract, TheManPageIsTheOneTheCommandTableGeneratesAndListsEverySubCommand) {
  const CliRun r = amb::test::run_cli(AMB_HOST_EXE, {"--man"}, work("man"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path page = fs::path(amb::test::source_dir()) / "packaging/man/amb-host.1";
  EXPECT_EQ(amb::test::read_text(page), r.out)
      << "packaging/man/amb-host.1 is not what the command table generates; regenerate it with "
         "'build/host-tools/amb-host --man > packaging/man/amb-host.1'";
  // The table is held here: a range-for over table()["commands"] iterates a member of a
  // temporary destroyed before the loop body (heap-use-after-free under ASan).
  const auto commands = table()["commands"];
  for (const auto& cmd : commands) {
    std::string roff;
    for (char c : cmd["path"].get<std::string>()) roff += c == '-' ? std::string("\\-") : std::string(1, c);
    EXPECT_NE(r.out.find(".SS " + roff + "\n"), std::string::npos) << "the man page lacks " << cmd["path"];
  }
  for (const char* section : {".SH EXIT STATUS", ".SH EXAMPLES", ".SH SUB-COMMANDS"})
    EXPECT_NE(r.out.find(section), std::string::npos) << section;
  // The firmware pages state the exit status too.
  for (const char* other : {"packaging/man/amb-firmware.8", "packaging/man/amb-plant.1"}) {
    const std::string text = amb::test::read_text(fs::path(amb::test::source_dir()) / other);
    EXPECT_NE(text.find(".SH EXIT STATUS"), std::string::npos) << other;
    EXPECT_NE(text.find("\\-\\-version"), std::string::npos) << other;
  }
}

TEST(CliContract, FirmwareExecutablesCheckNumbersLikeAmbHost) {
  struct Case {
    std::string exe;
    std::vector<std::string> args;
    std::string named;
  };
  std::vector<Case> cases;
  for (const char* v : {"abc", "-1", "inf", "nan", "1e400", "", "5x"})
    cases.push_back({AMB_FIRMWARE_EXE, {"--backend", "sim", "--duration-s", v}, "--duration-s"});
  cases.push_back({AMB_FIRMWARE_EXE, {"--duration-s", "7200", "--backend", "sim"}, "--duration-s"});
  cases.push_back({AMB_FIRMWARE_EXE, {"--board", "nosuch"}, "--board"});
  cases.push_back({AMB_FIRMWARE_EXE, {"--no-such-option"}, "--no-such-option"});
#ifdef AMB_PLANT_EXE
  for (const char* v : {"abc", "-1", "inf", "1.5"}) cases.push_back({AMB_PLANT_EXE, {"--seed", v, "--board", "bath-amb-rig"}, "--seed"});
  for (const char* v : {"abc", "0", "inf", "nan"})
    cases.push_back({AMB_PLANT_EXE, {"--duration-s", v, "--board", "bath-amb-rig"}, "--duration-s"});
  cases.push_back({AMB_PLANT_EXE, {"--board", "nosuch"}, "--board"});
#endif
  for (const auto& c : cases) {
    const CliRun r = amb::test::run_cli(c.exe, c.args, work("firmware"), 10.0);
    EXPECT_EQ(r.exit_code, 1) << c.exe << " " << amb::test::shown(c.args) << "\n" << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << c.exe << " " << amb::test::shown(c.args) << "\n" << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
  }
}

}  // namespace
