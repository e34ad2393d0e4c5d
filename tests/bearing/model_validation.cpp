// bearing-check on labelled records made with the project's bearing models (model_records.hpp):
// seed 003's 4-DOF model with the SKF 6206, the CWRU 6205 and the fan-end 6203, seed 001's 8-DOF
// rotor with two SKF 6200; outer- and inner-race grooves of 0.5 and 1 mm, shaft speeds, sample
// rates, noise levels and transfer paths; healthy records at settings the null calibration did
// not use. The checker gets the record, fs, a nominal speed 0.4 % off the true one and the
// bearing name. Prints the tables of docs/bearing.md. Label `long` (several minutes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "tests/bearing/model_records.hpp"

namespace hb = amb::host::bearing;
namespace mb = amb::model::bearing;
namespace tb = amb::test::bearing;

namespace {
struct Tally {
  int n = 0, right = 0, wrong_fault = 0, unclear = 0;
};

struct Tables {
  std::map<std::string, Tally> by_row;  // "<model> <bearing> <label>"
  std::map<std::string, Tally> by_label, by_noise, by_path, by_width, by_load, by_speed;
  std::map<std::string, std::map<std::string, int>> confusion;  // truth -> verdict -> count
};

// Runs bearing-check on every record, prints one line per record and the tables.
Tables evaluate(const std::vector<tb::RecordSpec>& specs) {
  Tables out;
  auto& [by_row, by_label, by_noise, by_path, by_width, by_load, by_speed, confusion] = out;
  int k = 0;
  for (const auto& s : specs) {
    const auto x = tb::make_record(s);
    EXPECT_FALSE(x.empty());
    if (x.empty()) continue;
    const double nominal = s.speed_hz * (k++ % 2 ? 1.004 : 0.996);
    const auto r = hb::check_bearing(x, s.fs_hz, nominal, *mb::find_bearing(s.bearing));
    const std::string truth = s.label();
    const bool right = r.verdict == truth;
    const bool wrong_fault = !right && r.verdict != "healthy" && r.verdict != "unclear";
    ++confusion[truth][r.verdict];
    auto add = [&](Tally& t) {
      ++t.n;
      t.right += right;
      t.wrong_fault += wrong_fault;
      t.unclear += r.verdict == "unclear";
    };
    add(by_row[s.model + " " + s.bearing + " " + truth]);
    add(by_label[truth]);
    if (truth != "healthy") {
      char key[64];
      std::snprintf(key, sizeof key, "%s noise %g", truth.c_str(), s.noise_rel);
      add(by_noise[key]);
      std::snprintf(key, sizeof key, "%s path %d", truth.c_str(), s.path);
      add(by_path[key]);
      std::snprintf(key, sizeof key, "%s width %.1f mm", truth.c_str(), s.width_mm);
      add(by_width[key]);
      std::snprintf(key, sizeof key, "%s load x %.1f", truth.c_str(), s.load_scale);
      add(by_load[key]);
      std::snprintf(key, sizeof key, "%s %s %2.0f Hz", truth.c_str(), s.model.c_str(), s.speed_hz);
      add(by_speed[key]);
    } else {
      char key[64];
      std::snprintf(key, sizeof key, "healthy noise %g", s.noise_rel);
      add(by_noise[key]);
    }
    // The named family's score and each other family's score / threshold (the misses' reasons).
    std::string scores;
    for (const auto& f : r.families) {
      char b[64];
      std::snprintf(b, sizeof b, " %s %.1f/%.1f", f.name.c_str(), f.score, f.threshold_score);
      scores += b;
    }
    std::printf("model %s %s %-10s w %.1f mm load x %.1f %4.0f Hz fs %5.0f noise %.2f path %d: %-10s%s %s\n",
                s.model.c_str(), s.bearing.c_str(), truth.c_str(), s.width_mm, s.load_scale, s.speed_hz, s.fs_hz,
                s.noise_rel, s.path, r.verdict.c_str(), scores.c_str(), right ? "" : r.reason.substr(0, 110).c_str());
    if (!right && truth != "healthy") {
      const std::string fam = truth == "outer_race" ? "bpfo" : truth == "inner_race" ? "bpfi" : "ball";
      std::printf("    %s: %s\n", fam.c_str(), r.family(fam).reason.substr(0, 200).c_str());
    }
  }
  auto table = [](const char* title, const std::map<std::string, Tally>& m) {
    std::printf("| %s | records | right | unclear | wrong fault named |\n| --- | --- | --- | --- | --- |\n", title);
    for (const auto& [key, t] : m) std::printf("| %s | %d | %d | %d | %d |\n", key.c_str(), t.n, t.right, t.unclear, t.wrong_fault);
  };
  table("model bearing truth", by_row);
  table("truth", by_label);
  table("truth, noise/signal", by_noise);
  table("truth, transfer path", by_path);
  table("truth, width", by_width);
  table("truth, load", by_load);
  table("truth, model, speed", by_speed);
  std::printf("| truth \\ verdict | outer_race | inner_race | ball | unclear | healthy |\n| --- | --- | --- | --- | --- | --- |\n");
  for (auto& [truth, row] : confusion)
    std::printf("| %s | %d | %d | %d | %d | %d |\n", truth.c_str(), row["outer_race"], row["inner_race"], row["ball"],
                row["unclear"], row["healthy"]);
  return out;
}
}  // namespace

namespace {
struct ValidationBearing {
  const char* model;
  const char* bearing;
  double duration_s;
  std::vector<double> fault_speeds, healthy_speeds;
};
const std::vector<ValidationBearing>& validation_bearings() {
  static const std::vector<ValidationBearing> b{{"4dof", "6206", 10, {20, 45}, {20, 35, 55}},
                                                {"4dof", "6205", 10, {20, 45}, {20, 35, 55}},
                                                {"4dof", "6203", 10, {20, 45}, {20, 35, 55}},
                                                {"8dof", "6200", 5, {25, 40}, {25, 40}}};
  return b;
}
// The healthy records of one bearing: speeds x noise 0.5 / 1 / 2 x paths 0 / 1 / 2 (12 / 20 /
// 48 kHz), seeds counting up; ball 0 oversized by ball_excess_um (0: equal balls).
void push_healthy(std::vector<tb::RecordSpec>& specs, const ValidationBearing& b, uint64_t& seed, double ball_excess_um) {
  for (double sp : b.healthy_speeds)
    for (double noise : {0.5, 1.0, 2.0})
      for (int path : {0, 1, 2}) {
        tb::RecordSpec s;
        s.model = b.model;
        s.bearing = b.bearing;
        s.speed_hz = sp;
        s.fs_hz = path == 1 ? 20000 : path == 0 ? 12000 : 48000;
        s.duration_s = b.duration_s;
        s.noise_rel = noise;
        s.path = path;
        s.seed = ++seed;
        s.ball_excess_um = ball_excess_um;
        specs.push_back(s);
      }
}
}  // namespace

TEST(BearingModelValidation, DetectionAndFalseAlarmRates) {
  std::vector<tb::RecordSpec> specs;
  uint64_t seed = 1000;
  for (const auto& b : validation_bearings()) {
    for (auto loc : {mb::DefectLocation::outer_race, mb::DefectLocation::inner_race})
      for (double w : {0.5, 1.0})
        for (double sp : b.fault_speeds)
          for (double noise : {0.5, 1.0})
            for (int path : {0, 2}) {
              tb::RecordSpec s;
              s.model = b.model;
              s.bearing = b.bearing;
              s.defect = loc;
              s.width_mm = w;
              s.speed_hz = sp;
              s.fs_hz = path == 0 ? 12000 : 48000;
              s.duration_s = b.duration_s;
              s.noise_rel = noise;
              s.path = path;
              s.seed = ++seed;
              specs.push_back(s);
            }
    push_healthy(specs, b, seed, 0.0);
  }
  auto tables = evaluate(specs);
  auto& by_label = tables.by_label;
  const auto& h = by_label["healthy"];
  const int false_alarms = h.n - h.right - h.unclear;
  std::printf("healthy: %d records, %d false alarms (a fault named), %d unclear\n", h.n, false_alarms, h.unclear);
  int race_n = 0, race_right = 0;
  for (const char* f : {"outer_race", "inner_race"}) {
    const auto& t = by_label[f];
    std::printf("%s: detected %d of %d (%.1f %%), wrong fault named %d\n", f, t.right, t.n, 100.0 * t.right / t.n,
                t.wrong_fault);
    race_n += t.n;
    race_right += t.right;
    EXPECT_EQ(t.wrong_fault, 0) << f;
    EXPECT_GE(100 * t.right, 95 * t.n) << f << ": detection below 95 % (issue 32: per race family)";
  }
  std::printf("race faults: %d of %d named right (%.1f %%)\n", race_right, race_n, 100.0 * race_right / race_n);
  // Issue 32's targets: race-fault detection >= 95 %, false alarms on healthy records <= 2 %.
  EXPECT_GE(100 * race_right, 95 * race_n);
  EXPECT_LE(100 * false_alarms, 2 * h.n) << "false-alarm rate above 2 %";
}

// Healthy bearings are not perfect: ISO 3290-1 lets the balls of one lot differ in diameter by
// 0.5 um (grade G10) to 1.4 um (G28). One ball larger than the others loads more as it goes round
// with the cage, so the record carries cage-rate (FTF) modulation - what the cage rules read as
// a ball fault. The 99 healthy settings above with ball 0 oversized by 0.25 / 0.5 / 1 um (fresh
// seeds: these records were not looked at when raw_cage_scan was turned off): false alarms <= 2 %
// at each excess with the default chain. Prints, for the record, the rate with the raw cage scan
// on (measured on other seeds: 27 of 396).
TEST(BearingModelValidation, HealthyWithBallSizeVariation) {
  int n_all = 0, fa_all = 0, fa_scan_all = 0;
  for (double excess : {0.25, 0.5, 1.0}) {
    std::vector<tb::RecordSpec> specs;
    uint64_t seed = 11000 + static_cast<uint64_t>(std::lround(excess * 1000));
    for (const auto& b : validation_bearings()) push_healthy(specs, b, seed, excess);
    int n = 0, fa = 0, unclear = 0, fa_scan = 0, k = 0;
    for (const auto& s : specs) {
      const auto x = tb::make_record(s);
      EXPECT_FALSE(x.empty());
      if (x.empty()) continue;
      const double nominal = s.speed_hz * (k++ % 2 ? 1.004 : 0.996);
      const auto g = *mb::find_bearing(s.bearing);
      const auto r = hb::check_bearing(x, s.fs_hz, nominal, g);
      hb::BearingCheckOptions scan;
      scan.raw_cage_scan = true;
      const auto rs = hb::check_bearing(x, s.fs_hz, nominal, g, scan);
      ++n;
      const bool named = r.verdict != "healthy" && r.verdict != "unclear";
      fa += named;
      unclear += r.verdict == "unclear";
      fa_scan += rs.verdict != "healthy" && rs.verdict != "unclear";
      if (named || rs.verdict != "healthy")
        std::printf("  %s %s %g Hz noise %g path %d excess %.2f um: %s (with the raw scan: %s)\n", s.model.c_str(),
                    s.bearing.c_str(), s.speed_hz, s.noise_rel, s.path, excess, r.verdict.c_str(), rs.verdict.c_str());
    }
    std::printf("ball excess %.2f um: %d healthy records, %d false alarms (%.1f %%), %d unclear; with the raw cage scan "
                "%d false alarms (%.1f %%)\n",
                excess, n, fa, 100.0 * fa / n, unclear, fa_scan, 100.0 * fa_scan / n);
    EXPECT_LE(100 * fa, 2 * n) << "false alarms above 2 % at ball excess " << excess << " um";
    n_all += n;
    fa_all += fa;
    fa_scan_all += fa_scan;
  }
  std::printf("all: %d records, %d false alarms (%.1f %%); with the raw cage scan %d (%.1f %%)\n", n_all, fa_all,
              100.0 * fa_all / n_all, fa_scan_all, 100.0 * fa_scan_all / n_all);
}

// The ball family's bounds (no target in issue 32, which sets race detection >= 95 % and false
// alarms <= 2 %): most ball faults named ball (the chain before cage_as_ball_modulation named
// 28 of BallRecords' 128), and a ball fault named as a race fault no more often than the 2 %
// false-alarm bound (set after BallRecords showed 2 of 128; before BallRecordsHeldOut ran).
void check_ball(Tables t, int records) {
  const auto& ball = t.by_label["ball"];
  std::printf("ball: detected %d of %d (%.1f %%), unclear %d, named a race fault %d\n", ball.right, ball.n,
              100.0 * ball.right / ball.n, ball.unclear, ball.wrong_fault);
  EXPECT_EQ(ball.n, records);
  EXPECT_GE(2 * ball.right, ball.n) << "fewer than half the ball faults named ball";
  EXPECT_LE(100 * ball.wrong_fault, 2 * ball.n) << "ball faults named as race faults above 2 %";
}

// A grid of ball-spot records: every bearing x spot width x load x speed x noise x path, in
// that order, seeds counting up from first_seed. Paths 0 / 1 / 2 are sampled at 12 / 20 / 48 kHz.
struct BallGrid {
  struct Bearing {
    const char* model;
    const char* bearing;
    double duration_s;
    std::vector<double> speeds_hz;
  };
  std::vector<Bearing> bearings;
  std::vector<double> widths_mm, loads, noises;
  std::vector<int> paths;
  uint64_t first_seed = 0;
};

std::vector<tb::RecordSpec> ball_specs(const BallGrid& g) {
  std::vector<tb::RecordSpec> specs;
  uint64_t seed = g.first_seed;
  for (const auto& b : g.bearings)
    for (double w : g.widths_mm)
      for (double load : g.loads)
        for (double sp : b.speeds_hz)
          for (double noise : g.noises)
            for (int path : g.paths) {
              tb::RecordSpec s;
              s.model = b.model;
              s.bearing = b.bearing;
              s.defect = mb::DefectLocation::ball;
              s.width_mm = w;
              s.load_scale = load;
              s.speed_hz = sp;
              s.fs_hz = path == 0 ? 12000 : path == 1 ? 20000 : 48000;
              s.duration_s = b.duration_s;
              s.noise_rel = noise;
              s.path = path;
              s.seed = seed++;
              specs.push_back(s);
            }
  return specs;
}

// Ball (rolling-element spot) records: same bearings, spot widths, speeds, noise levels and
// paths as the race records, at their load and at twice it (4-DOF: W_y 500 and 1000 N, of which the
// shaft support k1 takes the first ~370 N before the 5 um clearance closes; 8-DOF: discs x 1, x 2). Nothing of the chain
// is tuned on these (the null is the healthy records'). Prints the same tables and the
// confusion; asserts what the chain must never do: name a ball fault as a race fault.
TEST(BearingModelValidation, BallRecords) {
  BallGrid g;
  g.bearings = {{"4dof", "6206", 10, {20, 45}}, {"4dof", "6205", 10, {20, 45}}, {"4dof", "6203", 10, {20, 45}},
                {"8dof", "6200", 5, {25, 40}}};
  g.widths_mm = {0.5, 1.0};
  g.loads = {1.0, 2.0};
  g.noises = {0.5, 1.0};
  g.paths = {0, 2};
  g.first_seed = 5001;
  check_ball(evaluate(ball_specs(g)), 128);
}

// Ball records at settings neither the race records nor BallRecords use (spot widths 0.3 and
// 0.7 mm, load x 1.5, 4-DOF 30/40 Hz, 8-DOF 30/35 Hz, noise 0.75/1.5, paths 1 and 2), run once
// after the chain was settled on BallRecords: the held-out figure for the ball family.
TEST(BearingModelValidation, BallRecordsHeldOut) {
  BallGrid g;
  g.bearings = {{"4dof", "6206", 10, {30, 40}}, {"4dof", "6205", 10, {30, 40}}, {"4dof", "6203", 10, {30, 40}},
                {"8dof", "6200", 5, {30, 35}}};
  g.widths_mm = {0.3, 0.7};
  g.loads = {1.5};
  g.noises = {0.75, 1.5};
  g.paths = {1, 2};
  g.first_seed = 9001;
  check_ball(evaluate(ball_specs(g)), 64);
}
