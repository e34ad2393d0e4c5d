// Machine profiles and order discovery (issue 15): one wind-turbine profile for every record,
// the built-in default never reports a wrong speed with confidence, and a bad profile is refused
// with the key named. The code under test gets the record and the profile, nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/tracking/track_speed.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/tracking/windturbine_records.hpp"

namespace {
using namespace amb::test::windturbine;

// Mean relative error over valid updates, worst valid update, valid count.
struct Score {
  double mean = 0.0, worst = 0.0;
  size_t valid = 0, all = 0;
};
Score score(const amb::host::TrackSpeedResult& r, const std::vector<double>& tach) {
  Score s;
  for (size_t i = 0; i < r.t_s.size(); ++i) {
    const double truth = shaft_speed_hz(tach, r.t_s[i] - 0.5 * r.window_s, r.t_s[i] + 0.5 * r.window_s);
    if (!std::isfinite(truth)) continue;
    ++s.all;
    if (r.lost[i]) continue;
    const double e = std::abs(r.speed_hz[i] - truth) / truth;
    s.mean += e;
    s.worst = std::max(s.worst, e);
    ++s.valid;
  }
  if (s.valid) s.mean /= static_cast<double>(s.valid);
  return s;
}
}  // namespace

TEST(MachineProfile, WindTurbineProfileTracksEveryRecord) {
  const auto files = records();
  if (files.empty()) GTEST_SKIP() << "no records in " << record_dir();
  const auto prof = amb::host::load_machine_profile(std::string(amb::test::source_dir()) + "/profiles/windturbine-hss.toml");
  for (const auto& f : files) {
    const auto tach = amb::host::read_mat_vector(f, "tach");
    const auto r = amb::host::track_speed_with_profile(amb::host::read_mat_vector(f, "vibration"), k_fs_hz, prof);
    const Score s = score(r, tach);
    std::printf("profile windturbine-hss, %s: status %s, discovered %.3f Hz orders %zu, window %.2f s, %zu/%zu valid, "
                "mean err %.3f %%, worst %.3f %% (truth: tach pulse rate / 2)\n",
                std::filesystem::path(f).filename().c_str(), r.status.c_str(), r.discovery.speed_hz,
                r.discovery.orders.size(), r.window_s, s.valid, s.all, 100 * s.mean, 100 * s.worst);
    EXPECT_EQ(r.status, "ok") << f;
    EXPECT_GE(s.valid, s.all * 3 / 4) << f;
    EXPECT_LT(s.mean, 0.01) << f;
  }
}

TEST(MachineProfile, DefaultsNeverReportAWrongSpeed) {
  const auto files = records();
  if (files.empty()) GTEST_SKIP() << "no records in " << record_dir();
  for (const auto& f : files) {
    const auto tach = amb::host::read_mat_vector(f, "tach");
    const auto r = amb::host::track_speed_with_profile(amb::host::read_mat_vector(f, "vibration"), k_fs_hz,
                                                       amb::host::default_machine_profile());
    const Score s = score(r, tach);
    std::printf("default profile, %s: status %s (%s), %zu/%zu valid, worst %.3f %%\n",
                std::filesystem::path(f).filename().c_str(), r.status.c_str(), r.discovery.reason.c_str(), s.valid,
                s.all, 100 * s.worst);
    // Either right within 1 % or explicitly lost.
    if (s.valid > 0) {
      EXPECT_LT(s.worst, 0.01) << f;
    }
    if (r.status != "ok") {
      EXPECT_EQ(s.valid, 0u) << f;
    }
  }
}

TEST(MachineProfile, DiscoversOrdersOfASyntheticShaft) {
  // 1x..3x of a 47 Hz shaft (amplitudes 1, 0.5, 0.3) in white noise at 5 kHz: discovery must
  // find the speed and the three orders, and the default profile must track it within 1 %.
  const double fs = 5000.0, f0 = 47.0;
  std::vector<double> x(static_cast<size_t>(8.0 * fs));
  uint64_t s = 4242;
  for (size_t i = 0; i < x.size(); ++i) {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    const double t = static_cast<double>(i) / fs;
    x[i] = 2.0 * (static_cast<double>(s >> 11) / 9007199254740992.0 - 0.5) + 0.3 * std::sin(2 * M_PI * f0 * t) +
           0.15 * std::sin(2 * M_PI * 2 * f0 * t + 1.0) + 0.1 * std::sin(2 * M_PI * 3 * f0 * t + 2.0);
  }
  const auto r = amb::host::track_speed_with_profile(x, fs, amb::host::default_machine_profile());
  ASSERT_EQ(r.status, "ok") << r.discovery.reason;
  EXPECT_NEAR(r.discovery.speed_hz, f0, 0.01 * f0);
  ASSERT_GE(r.discovery.orders.size(), 3u);
  EXPECT_EQ(r.discovery.orders[0], 1.0);
  EXPECT_EQ(r.discovery.orders[1], 2.0);
  EXPECT_EQ(r.discovery.orders[2], 3.0);
  size_t valid = 0;
  for (size_t i = 0; i < r.t_s.size(); ++i)
    if (!r.lost[i]) {
      ++valid;
      EXPECT_NEAR(r.speed_hz[i], f0, 0.01 * f0);
    }
  EXPECT_GT(valid, r.t_s.size() / 2);
}

TEST(MachineProfile, BadProfilesNameTheKey) {
  auto err = [](const std::string& text) {
    try {
      amb::host::parse_machine_profile(text, "p.toml");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string ok = "schema = \"amb-machine/1\"\n[speed]\nmin_hz = 10\nmax_hz = 40\n";
  EXPECT_EQ(err(ok), "");
  EXPECT_NE(err("schema = \"amb-machine/2\"\n[speed]\nmin_hz = 10\nmax_hz = 40\n").find("schema"), std::string::npos);
  EXPECT_NE(err("schema = \"amb-machine/1\"\n[speed]\nmin_hz = 50\nmax_hz = 40\n").find("speed.max_hz"), std::string::npos);
  EXPECT_NE(err(ok + "max_acel_hz_per_s = 2\n").find("speed.max_acel_hz_per_s: unknown key"), std::string::npos);
  EXPECT_NE(err(ok + "max_accel_hz_per_s = -1\n").find("speed.max_accel_hz_per_s"), std::string::npos);
  EXPECT_NE(err(ok + "[orders]\ncomb = \"guess\"\n").find("orders.comb"), std::string::npos);
  EXPECT_NE(err(ok + "[orders]\ncomb = [1, -2]\n").find("orders.comb[1]"), std::string::npos);
  EXPECT_NE(err("schema = \"amb-machine/1\"\n[speed]\nmax_hz = 40\n").find("speed.min_hz"), std::string::npos);
  EXPECT_NE(err("schema = = 1").find("syntax"), std::string::npos);
  const auto p = amb::host::parse_machine_profile(ok + "[orders]\ncomb = [1, 2, 3.5]\n", "p.toml");
  EXPECT_FALSE(p.discover_orders);
  ASSERT_EQ(p.orders.size(), 3u);
  EXPECT_EQ(p.orders[2], 3.5);
}
