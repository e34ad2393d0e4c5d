// bearing-check on the wind-turbine high-speed-shaft records (../shared/data/measured/
// windturbine-hss): an inner-race fault grew to failure over March-April 2013. The bearing's
// geometry is not documented; its inner-race line lies near 4.66 x the tach pulse rate
// (data README), i.e. 9.32 x the shaft speed (2 pulses per revolution, tests/tracking). The check
// gets an order-only pseudo-bearing with that BPFI order (Z 16, gamma 0.165: BPFO 6.68, FTF
// 0.4175, BSF orders follow from the same numbers and are not claimed), the record and the tach's
// mean shaft speed. The growth must show: the inner-race family not detected on the first
// record, detected on every later one. (Only the inner-race family is meaningful here: the
// other families' orders come from the invented geometry, so the verdict is not asserted.)
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "tests/tracking/windturbine_records.hpp"

namespace hb = amb::host::bearing;
namespace mb = amb::model::bearing;
namespace wt = amb::test::windturbine;

TEST(BearingWindTurbine, InnerRaceGrowthIsSeen) {
  const auto files = wt::records();
  if (files.size() < 4) GTEST_SKIP() << "wind-turbine records not found";
  // gamma = 0.165 with D_m 100 mm -> D_b 16.5 mm; BPFI = Z/2 (1 + gamma) = 9.32.
  const mb::BearingGeometry g{"order-only HSS", 16, 16.5e-3, 100e-3, 0.0, "pseudo-bearing: BPFI order 9.32 only"};
  std::vector<double> score;
  std::vector<bool> detected;
  for (const auto& f : files) {
    const auto x = amb::host::read_mat_vector(f, "vibration");
    const auto tach = amb::host::read_mat_vector(f, "tach");
    const double shaft = wt::shaft_speed_hz(tach, 0.0, static_cast<double>(x.size()) / wt::k_fs_hz);
    const auto r = hb::check_bearing(x, wt::k_fs_hz, shaft, g);
    const auto& bpfi = r.family("bpfi");
    std::printf("%s: shaft %.2f Hz, bpfi score %.1f (threshold %.1f), found %.2f / predicted %.2f Hz, verdict %s\n",
                f.substr(f.rfind('/') + 1).c_str(), shaft, bpfi.score, bpfi.threshold_score,
                bpfi.found_hz.value_or(0.0), bpfi.predicted_hz, r.verdict.c_str());
    if (r.raw_cage.run)
      std::printf("  raw cage scan: %zu bands, best %.0f-%.0f Hz, score %.1f vs threshold %.1f (own null: %d draws, q99 %.2f)%s\n",
                  r.raw_cage.bands, r.raw_cage.band.low_hz, r.raw_cage.band.high_hz, r.raw_cage.score,
                  r.raw_cage.threshold_score, r.raw_cage.null.samples, r.raw_cage.null.q99,
                  r.raw_cage.detected ? ": detected (the pseudo-bearing's FTF order is invented)" : "");
    for (const auto& l : r.raw_cage.lines.lines) std::printf("    %s %.2f Hz ratio %.1f p %.2g\n", l.label.c_str(), l.hz, l.ratio, l.p_value);
    score.push_back(bpfi.score);
    detected.push_back(bpfi.detected);
  }
  EXPECT_FALSE(detected.front());
  for (size_t i = 1; i < detected.size(); ++i) EXPECT_TRUE(detected[i]) << files[i];
  EXPECT_GT(score.back(), score.front());
}
