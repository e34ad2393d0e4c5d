// track-speed profile runs on generated data with known truth (issue 15): a synthetic machine
// (shaft orders 1..3 + a non-integer bearing line + white noise, tests/tracking/test_signals.hpp)
// at several speeds, slow ramps, noise levels and sample rates. With a profile that brackets the
// speed, and with the built-in defaults: every reported update should be within 1 % of the truth
// or lost; the test bounds the measured exceptions (see the comment at the end).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host-tools/core/tracking/track_speed.hpp"
#include "tests/tracking/test_signals.hpp"

TEST(ProfileGenerated, WithinOnePercentOrLost) {
  const auto prof = amb::host::parse_machine_profile(
      "schema = \"amb-machine/1\"\n[speed]\nmin_hz = 5\nmax_hz = 200\nmax_accel_hz_per_s = 5\n[orders]\ncomb = \"discover\"\n",
      "generated.toml");
  int runs = 0, ok_runs = 0, bad_updates = 0, valid_updates = 0;
  for (double f0 : {12.0, 47.0, 150.0}) {
    for (double fs : {5000.0, 20000.0, 97656.0}) {
      for (double noise : {0.3, 3.0}) {
        for (bool use_profile : {true, false}) {
          // Slow ramp: +2 % over the 6 s record.
          auto speed = [f0](double t) { return f0 * (1.0 + 0.02 * t / 6.0); };
          const auto x = amb::test::synthetic_machine(speed, {{1.0, 1.0}, {2.0, 0.5}, {3.0, 0.3}, {3.57, 0.4}}, fs, 6.0,
                                                      noise, static_cast<uint64_t>(f0 + fs + 10 * noise));
          const auto r = amb::host::track_speed_with_profile(
              x, fs, use_profile ? prof : amb::host::default_machine_profile());
          size_t valid = 0, bad = 0;
          double worst = 0.0;
          for (size_t i = 0; i < r.t_s.size(); ++i) {
            if (r.lost[i]) continue;
            ++valid;
            const double truth = speed(r.t_s[i]);
            const double e = std::abs(r.speed_hz[i] - truth) / truth;
            worst = std::max(worst, e);
            bad += e >= 0.01 ? 1 : 0;
          }
          ++runs;
          ok_runs += r.status == "ok" && valid * 2 > r.t_s.size() ? 1 : 0;
          bad_updates += static_cast<int>(bad);
          valid_updates += static_cast<int>(valid);
          std::printf("generated %6.1f Hz fs %6.0f noise %.1f %-8s: %-9s orders %zu window %.2f s, %zu/%zu valid, "
                      "worst %.3f %%\n",
                      f0, fs, noise, use_profile ? "profile" : "default", r.status.c_str(), r.discovery.orders.size(),
                      r.window_s, valid, r.t_s.size(), 100 * worst);
        }
      }
    }
  }
  std::printf("generated: %d of %d runs tracked (ok, > half the updates valid), %d of %d reported updates off by >= 1 %%\n",
              ok_runs, runs, bad_updates, valid_updates);
  EXPECT_GE(ok_runs, runs / 2);
  // Measured (docs/tracking.md): 3 of 4148 reported updates off by >= 1 % (150 Hz at 5 kHz,
  // noise 3, defaults; worst 1.7 %) -- the goal "never" is not met on generated data; this bound
  // keeps it from getting worse.
  EXPECT_LE(bad_updates, valid_updates / 1000);
}

TEST(ProfileGenerated, TwoUnrelatedFamiliesWithoutProfileAreAmbiguous) {
  // A 30 Hz shaft (1x) and an unrelated 173 Hz comb (1x, 2x): with no profile nothing says which is
  // the shaft: every update lost. With a 10-40 Hz profile the shaft is tracked.
  const double fs = 5000.0;
  auto a = amb::test::synthetic_machine([](double) { return 30.0; }, {{1.0, 1.0}}, fs, 6.0, 0.5, 11);
  const auto b = amb::test::synthetic_machine([](double) { return 173.0; }, {{1.0, 1.0}, {2.0, 0.8}}, fs, 6.0, 0.0, 12);
  for (size_t i = 0; i < a.size(); ++i) a[i] += b[i];
  const auto r = amb::host::track_speed_with_profile(a, fs, amb::host::default_machine_profile());
  EXPECT_EQ(r.status, "ambiguous") << r.discovery.reason;
  for (size_t i = 0; i < r.lost.size(); ++i) EXPECT_TRUE(r.lost[i]);
  const auto prof = amb::host::parse_machine_profile(
      "schema = \"amb-machine/1\"\n[speed]\nmin_hz = 10\nmax_hz = 40\nmax_accel_hz_per_s = 2\n", "t.toml");
  const auto rp = amb::host::track_speed_with_profile(a, fs, prof);
  ASSERT_EQ(rp.status, "ok") << rp.discovery.reason;
  EXPECT_NEAR(rp.discovery.speed_hz, 30.0, 0.3);
}
