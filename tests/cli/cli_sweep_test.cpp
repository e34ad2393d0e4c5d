// The bad-input sweep (issue 36): every sub-command in amb-host's command table (read from
// `amb-host --command-table`, so a new sub-command or option joins the sweep by itself) x
// every numeric option given non-finite, non-numeric and out-of-range values x every input
// file given missing, empty, a directory, truncated and of the wrong kind. Each run must end
// within a timeout with exit code 1, name the option or the file on stderr, print nothing
// on stdout (no verdict) and write nothing (the working folder stays empty).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware/wear/wear_record.hpp"
#include "tests/cli/cli_run.hpp"
#include "tests/replay/sil_capture_run.hpp"
#include "tests/support/read_text.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fs = std::filesystem;
using amb::test::CliRun;

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << bytes;
}

/// Valid files of each kind (and what to give where a kind is expected but another comes).
struct Fixtures {
  fs::path dir;
  std::map<std::string, fs::path> valid;      ///< kind -> a valid file of it
  std::map<std::string, fs::path> truncated;  ///< kind -> the valid file cut in half
  std::map<std::string, fs::path> wrong;      ///< kind -> a file of another kind
  std::map<std::string, fs::path> garbage;    ///< kind -> random bytes under the kind's file name
  fs::path empty_file, missing, folder, empty_dir;
};

// ctest runs each case as its own process, two at a time: every process works below its own
// folder (a shared fixture folder was removed by one case while another read it).
fs::path sweep_root() { return fs::path(amb::test::artefact_dir()) / "cli_sweep" / std::to_string(::getpid()); }

const Fixtures& fixtures() {
  static const Fixtures f = [] {
    Fixtures x;
    x.dir = sweep_root() / "fixtures";
    fs::remove_all(x.dir);
    fs::create_directories(x.dir);
    const fs::path src = amb::test::source_dir(), shared = amb::test::shared_dir();
    // A board event from a SIL drop (the firmware's own writer), a measured event from the
    // shared synthetic drops, a CWRU record, the repository's board, profile and study.
    const auto& ev = amb::test::sil_capture().event_default;
    write_bytes(x.dir / "event.ambe", std::string(ev.begin(), ev.end()));
    for (const char* ext : {".json", ".csv"})
      fs::copy_file(shared / "data/synthetic" / (std::string("bath_drop_example_1") + ext),
                    x.dir / (std::string("drop") + ext), fs::copy_options::overwrite_existing);
    fs::copy_file(shared / "data/measured/cwru/1797_IR_7_DE12.mat", x.dir / "record.mat", fs::copy_options::overwrite_existing);
    fs::copy_file(src / "boards/bath-amb-rig.toml", x.dir / "board.toml", fs::copy_options::overwrite_existing);
    fs::copy_file(src / "profiles/windturbine-hss.toml", x.dir / "profile.toml", fs::copy_options::overwrite_existing);
    fs::copy_file(src / "studies/envelope-small.toml", x.dir / "study.toml", fs::copy_options::overwrite_existing);
    amb::fw::WearRecord w;
    w.sequence = 1;
    w.board_name = "bath-amb-rig";
    w.life_model = "test";
    const auto wb = amb::fw::encode_wear_record(w);
    write_bytes(x.dir / "wear.ambw", std::string(wb.begin(), wb.end()));
    // Stand-in model: only ever read after a bad number was refused at parse, or truncated.
    write_bytes(x.dir / "model.json", R"({"format": "amb-hybrid-model", "version": 1, "records": []})");
    x.valid = {{"ambe", x.dir / "event.ambe"},  {"event", x.dir / "drop.json"},     {"measured-event", x.dir / "drop.json"},
               {"mat", x.dir / "record.mat"},    {"board", x.dir / "board.toml"},   {"profile", x.dir / "profile.toml"},
               {"envelope-spec", x.dir / "study.toml"}, {"wear-record", x.dir / "wear.ambw"},
               {"hybrid-model", x.dir / "model.json"}};
    x.wrong = {{"ambe", x.dir / "record.mat"},          {"event", x.dir / "board.toml"},   {"measured-event", x.dir / "event.ambe"},
               {"mat", x.dir / "board.toml"},           {"board", x.dir / "profile.toml"}, {"profile", x.dir / "board.toml"},
               {"envelope-spec", x.dir / "board.toml"}, {"wear-record", x.dir / "event.ambe"},
               {"hybrid-model", x.dir / "drop.json"}};
    fs::create_directories(x.dir / "truncated");
    for (const auto& [kind, path] : x.valid) {
      const std::string all = amb::test::read_text(path);
      const fs::path t = x.dir / "truncated" / (kind + path.extension().string());
      write_bytes(t, all.substr(0, all.size() / 2));
      x.truncated[kind] = t;
    }
    // Random bytes under each kind's name (a damaged download, a wrong rename).
    fs::create_directories(x.dir / "garbage");
    uint32_t seed = 12345;
    std::string junk;
    for (int i = 0; i < 4096; ++i) {
      seed = seed * 1664525u + 1013904223u;
      junk += static_cast<char>(seed >> 24);
    }
    for (const auto& [kind, path] : x.valid) {
      const fs::path g = x.dir / "garbage" / (kind + path.extension().string());
      write_bytes(g, junk);
      x.garbage[kind] = g;
    }
    // A measured event whose sidecar is whole but whose CSV is cut in the middle of a row.
    fs::create_directories(x.dir / "truncated-csv");
    fs::copy_file(x.dir / "drop.json", x.dir / "truncated-csv" / "drop.json", fs::copy_options::overwrite_existing);
    {
      const std::string csv = amb::test::read_text(x.dir / "drop.csv");
      write_bytes(x.dir / "truncated-csv" / "drop.csv", csv.substr(0, csv.size() / 2 + 7));
    }
    // The truncated measured event keeps its CSV (so the sidecar, not the missing CSV, is what breaks).
    fs::copy_file(x.dir / "drop.csv", x.dir / "truncated" / "event.csv", fs::copy_options::overwrite_existing);
    fs::copy_file(x.dir / "drop.csv", x.dir / "truncated" / "measured-event.csv", fs::copy_options::overwrite_existing);
    x.empty_file = x.dir / "empty.ambe";
    write_bytes(x.empty_file, "");
    x.missing = x.dir / "no-such-file.dat";
    x.folder = x.dir / "a-folder";
    fs::create_directories(x.folder);
    x.empty_dir = x.dir / "inputs-dir";
    fs::create_directories(x.empty_dir);
    return x;
  }();
  return f;
}

nlohmann::json command_table() {
  const fs::path dir = sweep_root() / "table";
  fs::create_directories(dir);
  const CliRun r = amb::test::run_cli(AMB_HOST_EXE, {"--command-table"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

/// A value inside the option's range (for required numbers of the base command line).
std::string inside(const nlohmann::json& range) {
  const double lo = range["lo"], hi = range["hi"];
  double v = range["lo_open"].get<bool>() ? (hi > lo + 1.0 ? lo + 1.0 : 0.5 * (lo + hi)) : lo;
  if (range["integer"].get<bool>()) v = std::ceil(v);
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// The example's value of option `name` ("" if the example does not give it).
std::string example_value(const std::string& example, const std::string& name) {
  std::vector<std::string> tok;
  std::string t;
  for (char c : example + " ") {
    if (c == ' ') {
      if (!t.empty()) tok.push_back(t);
      t.clear();
    } else {
      t += c;
    }
  }
  for (size_t i = 0; i + 1 < tok.size(); ++i)
    if (tok[i] == name) return tok[i + 1];
  return {};
}

/// The base command line of a sub-command: its path, then every required option with a valid
/// value (a fixture for input files, a name in the working folder for outputs, a number in
/// range, the example's value otherwise). `skip`: the option under test (added by the case).
std::vector<std::string> base_args(const nlohmann::json& cmd, const std::string& skip) {
  std::vector<std::string> args, positionals;
  std::string word;
  for (char c : cmd["path"].get<std::string>() + " ") {
    if (c == ' ') {
      args.push_back(word);
      word.clear();
    } else {
      word += c;
    }
  }
  for (const auto& o : cmd["options"]) {
    const std::string name = o["name"];
    if (!o["required"].get<bool>() || name == skip) continue;
    std::string v;
    if (!o["file_kind"].is_null()) v = fixtures().valid.at(o["file_kind"].get<std::string>()).string();
    else if (o["output"].get<bool>()) v = "out-" + std::string(name[0] == '-' ? name.substr(2) : name);
    else if (!o["range"].is_null()) {
      v = example_value(cmd["example"], name);  // the example's number (it makes sense with the rest)
      if (v.empty()) v = inside(o["range"]);
    }
    else if (o["positional"].get<bool>()) v = fixtures().empty_dir.string();  // e.g. fleet add FILES
    else v = example_value(cmd["example"], name);
    EXPECT_FALSE(v.empty()) << cmd["path"] << ": no value for the required " << name;
    if (o["positional"].get<bool>()) positionals.push_back(v);
    else {
      args.push_back(name);
      args.push_back(v);
    }
  }
  args.insert(args.end(), positionals.begin(), positionals.end());
  return args;
}

/// Adds `name value` (or the positional `value`) to a base command line.
std::vector<std::string> with(std::vector<std::string> args, const nlohmann::json& opt, const std::string& value) {
  if (opt["positional"].get<bool>()) {
    args.push_back(value);
  } else {
    args.push_back(opt["name"]);
    args.push_back(value);
  }
  return args;
}

struct Tally {
  int runs = 0;
  double slowest_s = 0.0;
  std::string slowest;
};

/// One bad-input run and its checks. `named`: what stderr must mention (the option or the file).
void expect_refused(const std::vector<std::string>& args, const std::vector<std::string>& named, const std::string& what,
                    Tally& tally) {
  static int n = 0;
  const fs::path cwd = sweep_root() / "work" / std::to_string(n++);
  fs::remove_all(cwd);
  fs::create_directories(cwd);
  const CliRun r = amb::test::run_cli(AMB_HOST_EXE, args, cwd, 20.0);
  ++tally.runs;
  if (r.wall_s > tally.slowest_s) {
    tally.slowest_s = r.wall_s;
    tally.slowest = amb::test::shown(args);
  }
  const std::string ctx = "amb-host " + amb::test::shown(args) + "  [" + what + "]\nstderr: " + r.err;
  EXPECT_FALSE(r.timed_out) << "hangs: " << ctx;
  EXPECT_EQ(r.exit_code, 1) << ctx;
  bool mentions = false;
  for (const auto& s : named) mentions = mentions || (!s.empty() && r.err.find(s) != std::string::npos);
  std::string listed;
  for (const auto& s : named) listed += (listed.empty() ? "'" : " / '") + s + "'";
  EXPECT_TRUE(mentions) << "the error names none of " << listed << ": " << ctx;
  EXPECT_TRUE(r.out.empty()) << "bad input printed on stdout (a verdict?): " << r.out << "\n" << ctx;
  EXPECT_TRUE(fs::is_empty(cwd)) << "bad input wrote " << fs::directory_iterator(cwd)->path().filename() << ": " << ctx;
  if (!::testing::Test::HasFailure()) fs::remove_all(cwd);
}

TEST(CliSweep, EveryNumericOptionRefusesNonFiniteNonNumericAndOutOfRangeValues) {
  const nlohmann::json table = command_table();
  Tally tally;
  int numeric = 0;
  for (const auto& cmd : table["commands"]) {
    if (cmd["has_subcommands"].get<bool>()) continue;
    for (const auto& o : cmd["options"]) {
      const std::string type = o["type"];
      const bool is_number = type == "FLOAT" || type == "INT" || type == "UINT";
      if (!is_number) continue;
      ++numeric;
      ASSERT_FALSE(o["range"].is_null()) << cmd["path"] << " " << o["name"]
                                         << " has no range check (use cli::number/real/positive/whole)";
      const auto& rg = o["range"];
      const double lo = rg["lo"], hi = rg["hi"];
      char below[40], above[40];
      std::snprintf(below, sizeof below, "%.17g", rg["lo_open"].get<bool>() ? lo : lo - std::max(1.0, std::fabs(lo)));
      std::snprintf(above, sizeof above, "%.17g", hi * 10.0 + 1.0);
      std::vector<std::string> bad = {"nan", "inf", "-inf", "abc", "", "1e400", "1e3x", below, above};
      if (rg["integer"].get<bool>()) bad.push_back(inside(rg) + ".5");
      const std::vector<std::string> base = base_args(cmd, o["name"]);
      for (const auto& v : bad)
        expect_refused(with(base, o, v), {o["name"].get<std::string>()}, "number " + v, tally);
    }
  }
  EXPECT_GT(numeric, 40) << "the table lists fewer numeric options than amb-host has";
  std::printf("numeric sweep: %d runs; slowest %.2f s: %s\n", tally.runs, tally.slowest_s, tally.slowest.c_str());
}

TEST(CliSweep, EveryInputFileRefusesMissingEmptyFolderTruncatedAndWrongKind) {
  const nlohmann::json table = command_table();
  const Fixtures& fx = fixtures();
  Tally tally;
  int files = 0;
  for (const auto& cmd : table["commands"]) {
    if (cmd["has_subcommands"].get<bool>()) continue;
    for (const auto& o : cmd["options"]) {
      if (o["file_kind"].is_null()) continue;
      ++files;
      const std::string kind = o["file_kind"], name = o["name"];
      const std::vector<std::string> base = base_args(cmd, name);
      auto check = [&](const fs::path& p, const char* what) {
        // The file, the option, or the broken CSV of a measured event's sidecar.
        expect_refused(with(base, o, p.string()), {p.filename().string(), name, p.stem().string() + ".csv"},
                       std::string(what) + " " + kind, tally);
      };
      check(fx.missing, "missing");
      check(fx.empty_file, "empty");
      check(fx.folder, "folder");
      check(fx.truncated.at(kind), "truncated");
      check(fx.wrong.at(kind), "wrong kind");
      check(fx.garbage.at(kind), "random bytes");
      if (kind == "event" || kind == "measured-event") check(fx.dir / "truncated-csv" / "drop.json", "CSV cut mid-row");
    }
  }
  EXPECT_GT(files, 15) << "the table lists fewer input files than amb-host reads";
  std::printf("file sweep: %d runs; slowest %.2f s: %s\n", tally.runs, tally.slowest_s, tally.slowest.c_str());
}

TEST(CliSweep, EveryOutputFileInAMissingFolderIsRefusedBeforeAnyWork) {
  const nlohmann::json table = command_table();
  Tally tally;
  int outputs = 0;
  const fs::path nowhere = sweep_root() / "no-such-folder" / "out";
  for (const auto& cmd : table["commands"]) {
    if (cmd["has_subcommands"].get<bool>()) continue;
    for (const auto& o : cmd["options"]) {
      if (!o["output_file"].get<bool>()) continue;
      ++outputs;
      expect_refused(with(base_args(cmd, o["name"]), o, nowhere.string()), {o["name"].get<std::string>()},
                     "output in a missing folder", tally);
    }
  }
  EXPECT_FALSE(fs::exists(nowhere.parent_path())) << "a refused command created the folder";
  EXPECT_GE(outputs, 7) << "the table lists fewer output files than amb-host writes";
  std::printf("output sweep: %d runs; slowest %.2f s: %s\n", tally.runs, tally.slowest_s, tally.slowest.c_str());
}

// Every sub-command, also those without a number or a file to sweep (fleet list, ...): an
// unknown option and each missing required option or argument are exit 1 naming it.
TEST(CliSweep, EverySubCommandRefusesAnUnknownOptionAndAMissingRequiredOneByName) {
  const nlohmann::json table = command_table();
  Tally tally;
  int commands = 0;
  for (const auto& cmd : table["commands"]) {
    if (cmd["has_subcommands"].get<bool>()) continue;
    ++commands;
    expect_refused(with(base_args(cmd, ""), nlohmann::json{{"positional", false}, {"name", "--no-such-option"}}, "1"),
                   {"--no-such-option"}, "unknown option", tally);
    for (const auto& o : cmd["options"]) {
      if (!o["required"].get<bool>()) continue;
      const std::string name = o["name"];
      // The option's own name, or the positional's name in upper case as --help shows it.
      expect_refused(base_args(cmd, name), {name}, "missing " + name, tally);
    }
  }
  EXPECT_GE(commands, 20) << "the table lists fewer sub-commands than amb-host has";
  std::printf("sub-command sweep: %d commands, %d runs; slowest %.2f s: %s\n", commands, tally.runs, tally.slowest_s,
              tally.slowest.c_str());
}

TEST(CliSweep, CliElevenErrorsAreExitOneWithTheOptionNamed) {
  const fs::path cwd = sweep_root() / "cli11";
  fs::remove_all(cwd);
  fs::create_directories(cwd);
  struct Case {
    std::vector<std::string> args;
    std::string named;
  };
  const std::vector<Case> cases = {
      {{"replay"}, "EVENT"},                                   // required positional missing (CLI11 106)
      {{"fit", fixtures().valid.at("event").string(), "--no-such-option"}, "--no-such-option"},  // unknown option (109)
      {{"bearing-check", "--fs"}, "--fs"},                     // option without its value
      {{"no-such-command"}, "no-such-command"},                // unknown sub-command
      {{"hybrid"}, "train"},                                   // a sub-sub-command required
      {{"wear-id", fixtures().valid.at("event").string(), "--model", "4p"}, "--model"},
  };
  for (const auto& c : cases) {
    const CliRun r = amb::test::run_cli(AMB_HOST_EXE, c.args, cwd);
    EXPECT_EQ(r.exit_code, 1) << amb::test::shown(c.args) << "\n" << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << amb::test::shown(c.args) << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

TEST(CliSweep, MisleadingCasesOfTheIssueSayWhatIsWrong) {
  const fs::path cwd = sweep_root() / "messages";
  fs::remove_all(cwd);
  fs::create_directories(cwd);
  const Fixtures& fx = fixtures();
  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::vector<Case> cases = {
      // The unknown board is named as such (not "named by the event").
      {{"replay", fx.valid.at("ambe").string(), "--board", "nosuch"}, "'nosuch' is neither a board file nor an embedded board"},
      // A bad record is named before the missing arm key.
      {{"writeback", fx.truncated.at("wear-record").string()}, "is not a usable wear record"},
      // A typo in the store name creates nothing.
      {{"fleet", "--store", "typo.sqlite", "list"}, "does not exist"},
      // A board file given as a profile or a study.
      {{"track-speed", "--mat", fx.valid.at("mat").string(), "--var", "DE_time", "--fs", "12000", "--profile",
        fx.valid.at("board").string()},
       "is a board file, not a machine profile"},
      {{"envelope", fx.valid.at("board").string()}, "is a board file, not an envelope study spec"},
      // A board of another rig than the event's.
      {{"fit", fx.valid.at("event").string(), "--board", "unicamp-amb-rig"}, "--force"},
      {{"report", fx.valid.at("event").string(), "--board", "unicamp-amb-rig"}, "--force"},
      // `fleet add` may create its store, but not when it refuses every file: no store left,
      // no summary on stdout.
      {{"fleet", "--store", "new.sqlite", "add", fx.missing.string(), "--json"}, "cannot be read"},
      // (Where nothing can be analysed bearing-check gives no verdict; with a CWRU record the
      // file's own fs and RPM win over the command line, so that refusal is not reachable from
      // this fixture: tests/bearing/cli checks --fs/--rpm.)
  };
  for (const auto& c : cases) {
    const CliRun r = amb::test::run_cli(AMB_HOST_EXE, c.args, cwd);
    EXPECT_EQ(r.exit_code, 1) << amb::test::shown(c.args) << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << amb::test::shown(c.args) << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_TRUE(fs::is_empty(cwd)) << "a refused command left a file behind (typo.sqlite?)";
}

}  // namespace
