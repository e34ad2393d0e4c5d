// Measured 2 MW wind-turbine high-speed-shaft records (shared/data/measured/windturbine-hss):
// tachless speed from `vibration` (g, 97 656 Hz) against the tachometer pulse rate.
//
// Pulses per revolution: 2. Evidence (printed by PulsesPerRevolutionEvidence): in all four
// records the strongest low-frequency line sits at 0.500 x the pulse rate (31.17/62.37,
// 31.29/62.68, 30.05/60.05, 31.17/62.35 Hz/pulses per s), while nothing stands above the
// floor at 1.0 x the pulse rate; a 1x line with no line at the pulse rate means two pulses
// per shaft revolution. The tracker runs with a 1x comb (orders {1}) because the records
// show no harmonic series of the shaft.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/tracking/track_speed.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/tracking/windturbine_records.hpp"

namespace {
using namespace amb::test::windturbine;

// window_s: 1.5 s for this machine (its speed drifts <= 2 % over 3 s, so a long window
// costs no tracking error and buys 5 dB of line SNR: the 20130331 record's 1x line is only
// ~8 dB above the floor in a 0.5 s window); 0.5 s is seed 003's window, reported for
// comparison only.
amb::host::TrackSpeedOptions turbine_options(double window_s = 1.5) {
  amb::host::TrackSpeedOptions o;  // seed 003 STFT otherwise: Hamming, 8192 points
  o.tracker.stft.window_s = window_s;
  o.tracker.stft.overlap = 0.95;
  o.tracker.n_orders = 1;          // 1x only (see above)
  o.tracker.min_speed_hz = 10.0;
  o.tracker.max_speed_hz = 40.0;   // 2400 rpm: above the HSS generator speed range
  // A 2 MW rotor changes speed slowly (records drift <= 2 % in 3 s, ~0.2 Hz/s).
  o.tracker.max_accel_hz_per_s = 2.0;
  o.tracker.rate_step_hz_per_s = 1.0;
  return o;
}
}  // namespace

TEST(WindTurbine, PulsesPerRevolutionEvidence) {
  const auto files = records();
  if (files.empty()) GTEST_SKIP() << "no records in " << record_dir();
  for (const auto& f : files) {
    const auto tach = amb::host::read_mat_vector(f, "tach");
    const double rate = static_cast<double>(tach.size() - 1) / (tach.back() - tach.front());
    const auto r = amb::host::track_speed(amb::host::read_mat_vector(f, "vibration"), k_fs_hz, turbine_options());
    const double med = amb::host::median_speed_hz(r);
    std::printf("%s: pulse rate %.3f /s, median tracked 1x %.3f Hz, ratio pulse/1x %.3f\n",
                std::filesystem::path(f).filename().c_str(), rate, med, rate / med);
    EXPECT_NEAR(rate / med, k_pulses_per_rev, 0.05);
  }
}

TEST(WindTurbine, TrackedSpeedAgainstTachometer) {
  const auto files = records();
  if (files.empty()) GTEST_SKIP() << "no records in " << record_dir();
  for (double window_s : {1.5, 0.5}) {
    const amb::host::TrackSpeedOptions opt = turbine_options(window_s);
    const double half_window_s = 0.5 * opt.tracker.stft.window_s;
    for (const auto& f : files) {
      const auto tach = amb::host::read_mat_vector(f, "tach");
      const auto r = amb::host::track_speed(amb::host::read_mat_vector(f, "vibration"), k_fs_hz, opt);
      double sum_valid = 0.0, sum_all = 0.0;
      size_t n_valid = 0, n_all = 0;
      for (size_t i = 0; i < r.t_s.size(); ++i) {
        // Reference: mean pulse rate over the same window as the STFT frame / 2 pulses per rev.
        const double truth =
            shaft_speed_hz(tach, r.t_s[i] - half_window_s, r.t_s[i] + half_window_s);
        if (!std::isfinite(truth)) continue;
        ++n_all;
        if (r.lost[i]) {
          sum_all += 1.0;
          continue;
        }
        const double rel = std::abs(r.speed_hz[i] - truth) / truth;
        sum_valid += rel;
        sum_all += rel;
        ++n_valid;
      }
      ASSERT_GT(n_all, 0u);
      const double mre_valid = n_valid ? sum_valid / static_cast<double>(n_valid) : 1.0;
      const double mre_all = sum_all / static_cast<double>(n_all);
      const double lost = 1.0 - static_cast<double>(n_valid) / static_cast<double>(n_all);
      std::printf("window %.1f s, %s: %zu updates, lost %.1f %%, mean rel err %.2f %% over tracked "
                  "updates, %.2f %% counting lost as 100 %%\n",
                  window_s, std::filesystem::path(f).filename().c_str(), n_all, 100 * lost, 100 * mre_valid,
                  100 * mre_all);
      if (window_s != 1.5) continue;  // the seed window is reported, not asserted
      // Bound 1 %: a 1x line 15-20 dB above the floor in a 1.5 s Hamming window (main-lobe
      // half-width 1.3 Hz) is located to about 0.1 Hz (0.3 % of 31 Hz); the reference is a
      // pulse-count average over the same window (+-1 pulse in ~90: 1 %), and only the first
      // acquisition updates are lost (counted as 100 %): 1 % + 2/21 would be the worst case,
      // so the bound is on the tracked updates and the lost fraction separately.
      EXPECT_LT(mre_valid, 0.01) << f;
      EXPECT_LT(lost, 0.15) << f;
    }
  }
}
