// bearing-check's null, measured: each family's score at surrogate bases on the healthy
// calibration records (tests/bearing/calibration.hpp). Prints the fit to put in
// BearingCheckOptions::default_nulls() and fails if the defaults are less conservative than the
// measurement (a lower detection threshold than the measured null supports).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "tests/bearing/calibration.hpp"

namespace tb = amb::test::bearing;
namespace hb = amb::host::bearing;

TEST(BearingNull, DefaultsAreAtLeastTheMeasuredNull) {
  const auto records = tb::calibration_records(true);
  hb::BearingCheckOptions o;
  std::array<std::vector<double>, 4> draws;
  const auto fits = tb::calibrate(records, o, &draws);
  const char* names[4] = {"bpfo", "bpfi", "ball", "ftf"};
  const double threshold = std::log10(o.record_false_alarm / (2.0 * 4.0));  // 2 bands x 4 families
  for (size_t f = 0; f < 4; ++f) {
    const auto& m = fits[f];
    const auto& d = o.null[f];
    double above = 0;
    for (double v : draws[f]) above += v > d.score_at(threshold) ? 1 : 0;
    std::printf("null %-4s: {%d, %.3f, %.3f, %.3f, %.3f}: %d draws, median %.3f q90 %.3f scale %.3f -> threshold score %.2f (default %.2f); "
                "draws above the default threshold: %.0f\n",
                names[f], m.samples, m.median, m.q90, m.q99, m.scale, m.samples, m.median, m.q90, m.scale, m.score_at(threshold), d.score_at(threshold), above);
    std::vector<double> top = draws[f];
    std::sort(top.rbegin(), top.rend());
    std::printf("  largest draws:");
    for (size_t i = 0; i < 5 && i < top.size(); ++i) std::printf(" %.2f", top[i]);
    std::printf("\n");
    ASSERT_GE(m.samples, 200);
    // 0.01: the defaults are the printed fit rounded to 3 decimals.
    EXPECT_GE(d.score_at(threshold), m.score_at(threshold) - 0.01) << names[f];
  }
}

// The raw-signal cage scan (cage_modulation_as_ball (b), raw_cage_scan; off by default) has the
// record's own null: on every
// healthy calibration record its cage score stays below the record's threshold. The CWRU healthy
// record is the one that matters: its tonal 3-5 kHz bands put surrogate scores up to ~70, and its
// cage template scores 13 in 750-2250 Hz; a null pooled from the model-made records (largest
// draw 5.3) would call that a ball fault.
TEST(BearingNull, RawCageScanIsQuietOnTheHealthyRecords) {
  const auto records = tb::calibration_records(true);
  hb::BearingCheckOptions o;
  o.raw_cage_scan = true;
  for (const auto& r : records) {
    const auto res = hb::check_bearing(r.x, r.fs_hz, r.speed_hz, r.geometry, o);
    const auto& c = res.raw_cage;
    std::printf("%-22s raw cage scan: %zu bands, %d surrogates (median %.2f, q99 %.2f, scale %.2f), best %.0f-%.0f Hz "
                "score %.1f, threshold %.1f, log10 P %.1f\n",
                r.name.c_str(), c.bands, c.null.samples, c.null.median, c.null.q99, c.null.scale, c.band.low_hz,
                c.band.high_hz, c.score, c.threshold_score, c.log10_p);
    ASSERT_TRUE(c.run);
    EXPECT_GE(c.null.samples, o.raw_cage_min_surrogates) << r.name;
    EXPECT_FALSE(c.detected) << r.name;
    EXPECT_EQ(res.verdict, "healthy") << r.name;
  }
}
