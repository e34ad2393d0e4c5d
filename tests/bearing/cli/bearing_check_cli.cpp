// amb-host bearing-check on the command line: the file's fs / RPM win over a disagreeing command
// line (with a warning), non-finite or absurd --fs / --rpm are refused with exit 1 naming the
// option and no verdict, --end fan reads FE_time with the 6203, --help lists the catalogue.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/read_text.hpp"
#include "tests/support/test_paths.hpp"

#include <unistd.h>

namespace fs = std::filesystem;

namespace {
struct CliRun {
  int rc = -1;
  std::string out, err;
};
CliRun amb_host(const std::string& args) {
  // Per process: ctest runs the cases as separate processes, two at a time.
  const fs::path dir = fs::temp_directory_path() / ("amb_bearing_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path o = dir / "stdout", e = dir / "stderr";
  const int rc = std::system((std::string(AMB_HOST_EXE) + " " + args + " > '" + o.string() + "' 2> '" + e.string() + "'").c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, amb::test::read_text(o), amb::test::read_text(e)};
}
std::string cwru(const char* f) { return std::string(amb::test::shared_dir()) + "/data/measured/cwru/" + f + ".mat"; }
}  // namespace

TEST(BearingCheckCli, FileValuesWinAndDisagreementIsWarned) {
  if (!fs::exists(cwru("1797_Normal"))) GTEST_SKIP();
  const CliRun r = amb_host("bearing-check --json --mat '" + cwru("1797_Normal") + "' --fs 12000 --rpm 1797");
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["fs_hz"].get<double>(), 48000.0);
  EXPECT_EQ(j["verdict"], "healthy");
  EXPECT_NE(r.err.find("--fs 12000 disagrees with the file's fs = 48000"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--rpm"), std::string::npos) << r.err;  // 1797 agrees
  for (const char* k : {"bpfo", "bpfi", "ball", "ftf"}) {
    EXPECT_TRUE(j["families"][k].contains("score")) << k;
    EXPECT_FALSE(j["families"][k]["reason"].get<std::string>().empty()) << k;
  }
}

TEST(BearingCheckCli, AbsurdFsOrRpmIsRefusedNamingTheOption) {
  if (!fs::exists(cwru("1797_IR_7_DE12"))) GTEST_SKIP();
  for (const auto& [args, option] : {std::pair<std::string, std::string>{"--fs nan", "--fs"}, {"--fs inf", "--fs"},
                                     {"--fs -12000", "--fs"}, {"--fs 1e12", "--fs"}, {"--fs 0", "--fs"},
                                     {"--rpm nan", "--rpm"}, {"--rpm 0", "--rpm"}, {"--rpm -1797", "--rpm"},
                                     {"--rpm 1e300", "--rpm"}}) {
    const CliRun r = amb_host("bearing-check --json --mat '" + cwru("1797_IR_7_DE12") + "' " + args);
    EXPECT_EQ(r.rc, 1) << args;
    EXPECT_TRUE(r.out.empty()) << args << ": " << r.out;  // never a verdict
    EXPECT_NE(r.err.find(option), std::string::npos) << args << ": " << r.err;
  }
}

TEST(BearingCheckCli, FanEndAndCatalogue) {
  if (!fs::exists(cwru("1797_Normal"))) GTEST_SKIP();
  const CliRun r = amb_host("bearing-check --json --end fan --mat '" + cwru("1797_Normal") + "'");
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["variable"], "FE_time");
  EXPECT_EQ(j["bearing"], "SKF 6203");
  EXPECT_EQ(j["verdict"], "healthy");
  const CliRun h = amb_host("bearing-check --help");
  for (const char* name : {"SKF 6205", "SKF 6206", "SKF 6200", "SKF 6203", "BPFO", "FE_time"})
    EXPECT_NE(h.out.find(name), std::string::npos) << name;
}

// The raw cage scan is off unless asked for (--raw-cage-scan): 1750_B is healthy (not diagnosed)
// by default, JSON raw_cage_scan null; with the flag the scan runs and names it ball.
TEST(BearingCheckCli, RawCageScanOnlyWhenAskedFor) {
  if (!fs::exists(cwru("1750_B_7_DE12"))) GTEST_SKIP();
  const CliRun d = amb_host("bearing-check --json --mat '" + cwru("1750_B_7_DE12") + "'");
  ASSERT_EQ(d.rc, 0) << d.err;
  const auto jd = nlohmann::json::parse(d.out);
  EXPECT_EQ(jd["verdict"], "healthy");
  EXPECT_TRUE(jd["raw_cage_scan"].is_null());
  const CliRun s = amb_host("bearing-check --json --raw-cage-scan --mat '" + cwru("1750_B_7_DE12") + "'");
  ASSERT_EQ(s.rc, 0) << s.err;
  const auto js = nlohmann::json::parse(s.out);
  EXPECT_EQ(js["verdict"], "ball");
  ASSERT_TRUE(js["raw_cage_scan"].is_object());
  EXPECT_TRUE(js["raw_cage_scan"]["detected"].get<bool>());
}

// --plot writes the HTML page and names it on stderr; stdout stays JSON. A folder that does not
// exist is refused at parse, before any work, and nothing is written.
TEST(BearingCheckCli, PlotPage) {
  if (!fs::exists(cwru("1797_IR_7_DE12"))) GTEST_SKIP();
  const fs::path dir = fs::temp_directory_path() / ("amb_bearing_plot_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path page = dir / "page.html";
  const CliRun r = amb_host("bearing-check --json --plot '" + page.string() + "' --mat '" + cwru("1797_IR_7_DE12") + "'");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["verdict"], "inner_race");
  EXPECT_NE(r.err.find(page.string()), std::string::npos) << r.err;
  const std::string html = amb::test::read_text(page);
  EXPECT_NE(html.find("id=\"bearing-band-whitened_full\""), std::string::npos);
  const fs::path bad = dir / "no-such-folder" / "page.html";
  const CliRun b = amb_host("bearing-check --plot '" + bad.string() + "' --mat '" + cwru("1797_IR_7_DE12") + "'");
  EXPECT_NE(b.rc, 0);
  EXPECT_NE(b.err.find("--plot"), std::string::npos) << b.err;
  EXPECT_TRUE(b.out.empty()) << b.out;
  EXPECT_FALSE(fs::exists(bad));
  fs::remove_all(dir);
}
