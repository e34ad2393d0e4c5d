// Leave-one-file-out validation of bearing-check's decision constants on every CWRU file in
// ../shared/data/measured/cwru (issue 15). For each held-out file, the constants (dominance,
// impulsive_sigmas, top_guard_fraction) are chosen on a grid by the number of right verdicts on
// the other five files only (ties: the documented default), then the held-out file is run with
// them. Label `long` (about a minute): not in the default test run.
// Right: the file's label (IR -> inner_race, ORat6 -> outer_race, Normal -> healthy); for the ball
// record "unclear" is accepted as the documented principled answer (docs/bearing.md) and reported.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "model/bearing/catalogue.hpp"
#include "tests/support/test_paths.hpp"

namespace hb = amb::host::bearing;
namespace mb = amb::model::bearing;

namespace {
struct File {
  std::string name;
  double fs, rpm;
  std::string label;
};
struct Constants {
  double dominance, impulsive_sigmas, top_guard;
};
bool right(const std::string& label, const std::string& verdict) {
  return verdict == label || (label == "ball" && verdict == "unclear");
}
}  // namespace

TEST(BearingLeaveOneOut, CwruFiles) {
  const std::string dir = std::string(amb::test::shared_dir()) + "/data/measured/cwru/";
  const std::vector<File> files{{"1750_IR_7_DE12", 12000, 1750, "inner_race"},
                                {"1797_IR_7_DE12", 12000, 1797, "inner_race"},
                                {"1750_ORat6_7_DE12", 12000, 1750, "outer_race"},
                                {"1797_ORat6_7_DE12", 12000, 1797, "outer_race"},
                                {"1797_B_7_DE12", 12000, 1797, "ball"},
                                {"1797_Normal", 48000, 1797, "healthy"}};
  for (const auto& f : files)
    if (!std::filesystem::exists(dir + f.name + ".mat")) GTEST_SKIP() << "no " << f.name;
  std::vector<Constants> grid;
  for (double d : {2.0, 1.5, 3.0})
    for (double s : {3.0, 0.0, 6.0})
      for (double g : {0.15, 0.05, 0.25}) grid.push_back({d, s, g});  // first entry: the default
  const auto geometry = *mb::find_bearing("6205");
  // verdict[file][constants]
  std::vector<std::vector<std::string>> verdict(files.size(), std::vector<std::string>(grid.size()));
  for (size_t i = 0; i < files.size(); ++i) {
    const auto x = amb::host::read_mat_vector(dir + files[i].name + ".mat", "DE_time");
    for (size_t c = 0; c < grid.size(); ++c) {
      hb::BearingCheckOptions o;
      o.dominance = grid[c].dominance;
      o.impulsive_sigmas = grid[c].impulsive_sigmas;
      o.band.top_guard_fraction = grid[c].top_guard;
      verdict[i][c] = hb::check_bearing(x, files[i].fs, files[i].rpm / 60.0, geometry, o).verdict;
    }
  }
  int held_out_right = 0;
  for (size_t h = 0; h < files.size(); ++h) {
    size_t best = 0;
    int best_n = -1;
    for (size_t c = 0; c < grid.size(); ++c) {
      int n = 0;
      for (size_t i = 0; i < files.size(); ++i)
        if (i != h && right(files[i].label, verdict[i][c])) ++n;
      if (n > best_n) {
        best_n = n;
        best = c;
      }
    }
    const bool ok = right(files[h].label, verdict[h][best]);
    held_out_right += ok ? 1 : 0;
    std::printf("held out %-18s chosen dominance %.1f impulsive_sigmas %.0f top_guard %.2f (%d/5 right on the rest) "
                "-> %s (%s)\n",
                files[h].name.c_str(), grid[best].dominance, grid[best].impulsive_sigmas, grid[best].top_guard, best_n,
                verdict[h][best].c_str(), ok ? "right" : "WRONG");
  }
  int default_right = 0;
  for (size_t i = 0; i < files.size(); ++i) default_right += right(files[i].label, verdict[i][0]) ? 1 : 0;
  std::printf("leave-one-out: %d/%zu held-out verdicts right; defaults on all files: %d/%zu\n", held_out_right,
              files.size(), default_right, files.size());
  // Sensitivity: how many constant sets give every file right.
  int all_right = 0;
  for (size_t c = 0; c < grid.size(); ++c) {
    int n = 0;
    for (size_t i = 0; i < files.size(); ++i) n += right(files[i].label, verdict[i][c]) ? 1 : 0;
    all_right += n == static_cast<int>(files.size()) ? 1 : 0;
    std::printf("  dominance %.1f impulsive_sigmas %.0f top_guard %.2f: %d/%zu right\n", grid[c].dominance,
                grid[c].impulsive_sigmas, grid[c].top_guard, n, files.size());
  }
  std::printf("constant sets with every file right: %d of %zu\n", all_right, grid.size());
  EXPECT_EQ(held_out_right, static_cast<int>(files.size()));
}
