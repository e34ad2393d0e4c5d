// The board's speed through a drop (issue 32): the main job's SIL scenario (bath-amb-rig, speed
// source tracker, no fit, no residual loop). After the AMB cut nothing drives the rotor, which
// coasts down on its touchdown bearings while the orbit's strongest line is the whirl. Every
// millisecond after the cut the board's speed, as its loop sees it, must be within 5 % of the
// plant's spin speed or be "not tracked" (NaN, lost) - never a confident wrong speed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "host-tools/core/scenario/drop_scenario.hpp"

TEST(DropTracker, NoTrackedSampleOffByMoreThanFivePercentAfterTheCut) {
  amb::host::DropScenarioOptions o;
  o.fit = false;
  o.residual = false;
  o.out_dir = (std::filesystem::temp_directory_path() / "amb_drop_tracker_test").string();
  const auto s = amb::host::run_drop_scenario(o);
  ASSERT_TRUE(s.fault_detected);
  const auto& tr = s.trace;
  ASSERT_EQ(tr.tracked_speed_hz.size(), tr.t_s.size());
  int after = 0, tracked = 0, off = 0;
  double worst = 0.0;
  for (size_t i = 0; i < tr.t_s.size(); ++i) {
    if (tr.t_s[i] <= s.cut_time_s) continue;
    ++after;
    const double v = tr.tracked_speed_hz[i];
    if (!std::isfinite(v)) continue;
    ++tracked;
    const double err = std::abs(v - tr.speed_hz[i]) / tr.speed_hz[i];
    worst = std::max(worst, err);
    if (err > 0.05) ++off;
    if (err > 0.05 || tracked % 10 == 1)
      std::printf("  t - t_cut %.3f s: plant %.2f Hz, board %.2f Hz\n", tr.t_s[i] - s.cut_time_s, tr.speed_hz[i], v);
  }
  std::printf("after the cut (%.1f Hz -> %.1f Hz): %d samples, %d tracked (worst error %.2f %%), %d off by > 5 %%\n",
              s.speed_at_cut_hz, s.speed_end_hz, after, tracked, 100.0 * worst, off);
  EXPECT_GT(after, 1000);
  EXPECT_EQ(off, 0);
}
