// The residual loop on real data: the TUM MLPS current-to-acceleration sweep
// (data/measured/tum-mlps-amb-sweep) against boards/tum-mlps-rig.toml. Prints what the
// model lacked and the error before and after; checks that the fit is meaningful and that
// whatever was added earned its parameters and lowered the error.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;

TEST(ResidualTum, MeasuredSweepLoop) {
  const std::string dir = std::string(amb::test::shared_dir()) + "/data/measured/tum-mlps-amb-sweep";
  if (!std::filesystem::exists(dir + "/Sweep_Time_Anregung.mat")) GTEST_SKIP() << "no TUM data at " << dir;
  const auto in = host::read_mat_vector(dir + "/Sweep_Time_Anregung.mat", "Signal.y_values.values");
  const auto dt = host::read_mat_scalar(dir + "/Sweep_Time_Anregung.mat", "Signal.x_values.increment");
  const auto acc = host::read_mat_matrix(dir + "/Sweep_Time_Ausgang.mat", "Signal_0.y_values.values");
  ASSERT_EQ(acc.cols, 8u);
  ASSERT_EQ(acc.rows, in.size());
  std::vector<std::vector<double>> out(8);
  for (size_t c = 0; c < 8; ++c) {
    out[c] = acc.column(c);
    for (double& v : out[c]) v *= 9.80665;  // g -> m/s^2
  }
  const auto b = board::load_board(std::string(amb::test::source_dir()) + "/boards/tum-mlps-rig.toml");
  const auto o = host::residual::run_sweep_residual(in, out, 1.0 / dt, b);
  std::printf("[ RESULT ] TUM MLPS sweep: %d segments, verdict %s\n", o.frf.segments, o.verdict.c_str());
  std::printf("[ RESULT ] error before: rms %.3f (ln), spectral %.2f dB, pearson %.3f; cost %.4g, BIC %.4g\n",
              o.before.error.rms, o.before.error.spectral, o.before.error.pearson, o.before.cost, o.before.bic);
  std::printf("[ RESULT ] error after : rms %.3f (ln), spectral %.2f dB, pearson %.3f; cost %.4g, BIC %.4g\n",
              o.after.error.rms, o.after.error.spectral, o.after.error.pearson, o.after.cost, o.after.bic);
  for (const auto& n : o.notes) std::printf("           note: %s\n", n.c_str());
  for (const auto& c : o.ranking) std::printf("           rank %-20s dBIC %10.1f  %s\n", c.name.c_str(), c.delta_bic, c.evidence.c_str());
  for (const auto& a : o.effects_added) {
    std::printf("           added %s:", a.name.c_str());
    for (const auto& [k, v] : a.parameters) std::printf(" %s=%.4g", k.c_str(), v);
    std::printf("\n");
  }
  std::printf("           after: excited axis %d, gain scale %.3f, positions (mm):", o.after.excited_axis, o.after.gain_scale);
  for (double z : o.after.accel_axial_m) std::printf(" %.0f", z * 1e3);
  std::printf("\n");
  EXPECT_GT(o.frf.segments, 20);
  EXPECT_GT(o.before.error.pearson, 0.3);        // the board's model explains the FRF shape
  if (!o.effects_added.empty()) {
    EXPECT_LT(o.after.bic, o.before.bic - 10.0);
    EXPECT_LT(o.after.error.spectral, o.before.error.spectral);
  }
}
