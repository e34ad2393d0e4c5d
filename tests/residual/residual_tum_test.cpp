// The residual loop on real data: the TUM MLPS current-to-acceleration sweep
// (data/measured/tum-mlps-amb-sweep) against boards/tum-mlps-rig.toml. Model updating of the
// half-open rotor-AMB model (frequencies first, then the complex FRF), elements kept by BIC,
// modal frequencies and MAC, and a validation on held-back accelerometers. Prints every
// figure; asserts properties that a broken estimator, model or fit would violate.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;

TEST(ResidualTum, MeasuredSweepModelUpdating) {
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
  host::residual::SweepOptions opt;
  opt.max_evaluations = 250;   // per bounded fit; the doc table gives the figures of this setting
  const auto o = host::residual::run_sweep_residual(in, out, 1.0 / dt, b, opt);
  std::printf("[ RESULT ] TUM MLPS sweep: %d segments, verdict %s\n", o.frf.segments, o.verdict.c_str());
  std::printf("[ RESULT ] before: spectral %.2f dB, pearson %.3f, rms %.3f (ln); BIC %.4g\n", o.before.error.spectral,
              o.before.error.pearson, o.before.error.rms, o.before.bic);
  std::printf("[ RESULT ] after : spectral %.2f dB, pearson %.3f, rms %.3f (ln); BIC %.4g\n", o.after.error.spectral,
              o.after.error.pearson, o.after.error.rms, o.after.bic);
  for (const auto& n : o.notes) std::printf("           note: %s\n", n.c_str());
  for (const auto& c : o.ranking) std::printf("           rank %-20s dBIC %10.1f  %s\n", c.name.c_str(), c.delta_bic, c.evidence.c_str());
  for (size_t i = 0; i < o.parameters.size(); ++i) {
    const auto& p = o.parameters[i];
    std::printf("           param %-24s %11.4g %-4s nominal %11.4g bounds [%g, %g]%s%s\n", p.name.c_str(), p.value, p.unit.c_str(),
                p.nominal, p.lower, p.upper, p.free ? "" : " (held)", o.parameter_at_bound[i] ? " AT BOUND" : "");
  }
  std::printf("           identifiability: rank %d of %zu, condition %.3g\n", o.identifiability.rank, o.identifiability.names.size(),
              o.identifiability.condition);
  for (size_t k = 0; k < o.modes_after.size(); ++k)
    std::printf("           mode %7.2f Hz: before %7.2f Hz MAC %.3f | after %7.2f Hz (%+.2f %%) MAC %.3f\n", o.modes_after[k].measured_hz,
                o.modes_before[k].model_hz, o.modes_before[k].mac, o.modes_after[k].model_hz, o.modes_after[k].error_pct,
                o.modes_after[k].mac);
  for (const auto& v : o.validation)
    std::printf("           validation fit ch%zu.. : fitted %.2f dB / %.3f, held-back %.2f dB / %.3f (board model on held-back %.2f dB / %.3f)\n",
                v.fit_channels.front() + 1, v.fit.spectral_db, v.fit.pearson, v.check.spectral_db, v.check.pearson,
                v.check_nominal.spectral_db, v.check_nominal.pearson);

  EXPECT_GT(o.frf.segments, 20);
  // The rub / saturation burst while the sweep passes the rigid-body resonance (RIG.md: t ~ 1.7-2.0 s).
  ASSERT_FALSE(o.nonlinear.empty());
  EXPECT_LT(o.nonlinear.front().t0_s, 1.75);
  EXPECT_GT(o.nonlinear.front().t1_s, 1.95);
  EXPECT_LT(o.nonlinear.front().t1_s - o.nonlinear.front().t0_s, 1.5);
  // Peaks from the data: the bending modes near 16, 100, 163 Hz and the pair near 204 / 212 Hz.
  auto found = [&](double f) {
    for (const auto& m : o.modes_after)
      if (std::abs(m.measured_hz / f - 1.0) < 0.03) return true;
    return false;
  };
  for (double f : {100.0, 163.0, 204.0, 212.0}) EXPECT_TRUE(found(f)) << "no measured peak near " << f << " Hz";
  // Updating must improve on the board's model in level, shape and information criterion.
  EXPECT_LT(o.after.error.spectral, o.before.error.spectral - 3.0);
  EXPECT_GT(o.after.error.pearson, o.before.error.pearson);
  EXPECT_LT(o.after.bic, o.before.bic);
  // Held-back channels: the parameters fitted on the other half must predict them better
  // than the board's model does (positions are the only per-channel nuisance).
  ASSERT_EQ(o.validation.size(), 2u);
  for (const auto& v : o.validation) EXPECT_LT(v.check.spectral_db, v.check_nominal.spectral_db);
}
