// Leave-one-file-out validation of bearing-check on the CWRU records in
// ../shared/data/measured/cwru. What is tuned: the null of the family scores (measured on healthy
// records: tests/bearing/calibration.hpp) and three choices - comb_dominance {2, 1.5, 3},
// slip_tolerance {0.015, 0.01, 0.02}, raw_sk_band {off, on}. For each held-out file the null is
// re-measured without that file (the healthy record's channels leave the calibration when it is
// held out), cage_modulation_as_ball {on, off} is a fourth choice, and the choices are made by the verdicts on the other nine files only (ties: the
// default), then the held-out file is run. Label `long` (a few minutes).
// Not a choice: raw_cage_scan stays off. It would name 1750_B and so win on these files, but it
// names 6.8 % of healthy model bearings with ordinary ball-size variation `ball` (above the 2 %
// bound; docs/bearing.md): an option whose false-alarm rate is out of bounds is not admissible,
// whatever it does on ten files with one healthy record.
// Right: IR -> inner_race, ORat6 -> outer_race, Normal -> healthy, B -> ball; for a ball record
// "unclear" or "healthy" is "not diagnosed" (Smith & Randall 2015: ball faults on this rig are
// mostly not diagnosable by envelope analysis), counted apart; a race name on it is wrong.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/bearing/calibration.hpp"

namespace hb = amb::host::bearing;
namespace mb = amb::model::bearing;
namespace tb = amb::test::bearing;

namespace {
struct File {
  std::string name;
  std::string label;
};
struct Choice {
  double comb_dominance, slip;
  bool raw_sk, cage_ball;
};
enum Outcome { kRight = 2, kNotDiagnosed = 1, kWrong = 0 };
Outcome judge(const std::string& label, const std::string& verdict) {
  if (verdict == label) return kRight;
  if (label == "ball" && (verdict == "unclear" || verdict == "healthy")) return kNotDiagnosed;
  return kWrong;
}
}  // namespace

TEST(BearingLeaveOneOut, CwruFiles) {
  const std::vector<File> files{{"1730_IR_7_DE12", "inner_race"},    {"1750_IR_7_DE12", "inner_race"},
                                {"1797_IR_7_DE12", "inner_race"},    {"1730_ORat6_7_DE12", "outer_race"},
                                {"1750_ORat6_7_DE12", "outer_race"}, {"1797_ORat6_7_DE12", "outer_race"},
                                {"1730_B_7_DE12", "ball"},           {"1750_B_7_DE12", "ball"},
                                {"1797_B_7_DE12", "ball"},           {"1797_Normal", "healthy"}};
  for (const auto& f : files)
    if (!std::filesystem::exists(tb::cwru_path(f.name))) GTEST_SKIP() << "no " << f.name;
  std::vector<Choice> grid;
  for (double d : {2.0, 1.5, 3.0})
    for (double s : {0.015, 0.01, 0.02})
      for (bool raw : {false, true})
        for (bool cage : {true, false}) grid.push_back({d, s, raw, cage});  // first entry: the defaults
  const auto g = *mb::find_bearing("6205");
  std::vector<std::vector<double>> x;
  std::vector<double> fs, speed;
  for (const auto& f : files) {
    const auto p = tb::cwru_path(f.name);
    x.push_back(amb::host::read_mat_vector(p, "DE_time"));
    fs.push_back(amb::host::read_mat_scalar(p, "fs"));
    speed.push_back(amb::host::read_mat_scalar(p, "RPM") / 60.0);
  }
  const auto with_normal = tb::calibration_records(true);
  const auto without_normal = tb::calibration_records(false);
  // outcome[calibration (0: with the healthy record, 1: without)][choice][file]
  std::vector<std::vector<std::vector<Outcome>>> outcome(2, std::vector<std::vector<Outcome>>(grid.size()));
  std::vector<std::vector<std::string>> verdict0(grid.size());  // with the healthy record's null
  for (int cal = 0; cal < 2; ++cal) {
    for (size_t c = 0; c < grid.size(); ++c) {
      hb::BearingCheckOptions o;
      o.comb_dominance = grid[c].comb_dominance;
      o.slip_tolerance = grid[c].slip;
      o.raw_sk_band = grid[c].raw_sk;
      o.cage_modulation_as_ball = grid[c].cage_ball;
      o.null = tb::calibrate(cal == 0 ? with_normal : without_normal, o);
      for (size_t i = 0; i < files.size(); ++i) {
        const auto v = hb::check_bearing(x[i], fs[i], speed[i], g, o).verdict;
        outcome[static_cast<size_t>(cal)][c].push_back(judge(files[i].label, v));
        if (cal == 0) verdict0[c].push_back(v);
      }
    }
  }
  int right = 0, not_diagnosed = 0, wrong = 0;
  for (size_t h = 0; h < files.size(); ++h) {
    const size_t cal = files[h].label == "healthy" ? 1 : 0;
    size_t best = 0;
    int best_n = -1;
    for (size_t c = 0; c < grid.size(); ++c) {
      int n = 0;
      for (size_t i = 0; i < files.size(); ++i)
        if (i != h) n += static_cast<int>(outcome[cal][c][i]);
      if (n > best_n) {
        best_n = n;
        best = c;
      }
    }
    const Outcome r = outcome[cal][best][h];
    right += r == kRight;
    not_diagnosed += r == kNotDiagnosed;
    wrong += r == kWrong;
    std::printf("held out %-18s null %s; chosen comb_dominance %.1f slip %.3f raw_sk %d cage_ball %d (score %d/18 on the "
                "rest) -> %s\n",
                files[h].name.c_str(), cal ? "without the healthy record" : "with the healthy record",
                grid[best].comb_dominance, grid[best].slip, grid[best].raw_sk, grid[best].cage_ball, best_n,
                r == kRight ? "right" : r == kNotDiagnosed ? "not diagnosed" : "WRONG");
  }
  std::printf("leave-one-out: %d right, %d not diagnosed (ball), %d wrong of %zu\n", right, not_diagnosed, wrong,
              files.size());
  for (size_t c = 0; c < grid.size(); ++c) {
    std::printf("  comb_dominance %.1f slip %.3f raw_sk %d cage_ball %d:", grid[c].comb_dominance, grid[c].slip,
                grid[c].raw_sk, grid[c].cage_ball);
    for (size_t i = 0; i < files.size(); ++i) std::printf(" %s", verdict0[c][i].c_str());
    std::printf("\n");
  }
  EXPECT_EQ(wrong, 0);
  // Every race-fault record, the healthy one, and 1730_B (its cage family alone, rule a); 1750_B
  // and 1797_B not diagnosed (measured 2026-11-29; 9 right while the raw cage scan was on).
  EXPECT_GE(right, 8);
}
