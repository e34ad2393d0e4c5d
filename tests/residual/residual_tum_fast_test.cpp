// Fast part of the TUM MLPS sweep checks (default test set; the whole model-updating loop is
// residual_tum_test.cpp, label `long`): the record read in SI units, the data side of the
// loop (rub / saturation burst found from the time data, H1 estimate, resonance peaks incl.
// the split pair near 204 / 212 Hz, the common-pole modal fit splitting that pair into two
// poles of one shaft shape) and the
// modal fit recovering known poles and shapes from a generated two-mode FRF; the model's
// eddy-current factor.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/residual/modal_peaks.hpp"
#include "host-tools/core/residual/nonlinear_span.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"
#include "model/analysis/half_open_frf.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;
using cd = std::complex<double>;

namespace {

std::string tum_dir() { return std::string(amb::test::shared_dir()) + "/data/measured/tum-mlps-amb-sweep"; }

bool has_tum() { return std::filesystem::exists(tum_dir() + "/Sweep_Time_Anregung.mat"); }

}  // namespace

// The stored accelerations are SI (Test.Lab "MKS"); the unit transformation is the display
// factor to g. The burst while the sweep passes the rigid-body resonance stays below 100 m/s^2.
TEST(ResidualTumFast, SweepFilesReadInSiUnits) {
  if (!has_tum()) GTEST_SKIP() << "no TUM data at " << tum_dir();
  const auto r = host::residual::read_tum_sweep(tum_dir());
  EXPECT_NEAR(r.fs_hz, 2048.0, 1e-9);
  ASSERT_EQ(r.accel_m_s2.size(), 8u);
  EXPECT_EQ(r.command_v.size(), r.current_a.size());
  EXPECT_NEAR(r.accel_display_factor, 1.0 / 9.80665, 1e-5);
  double peak = 0.0;
  for (const auto& c : r.accel_m_s2)
    for (double v : c) peak = std::max(peak, std::abs(v));
  EXPECT_GT(peak, 50.0);
  EXPECT_LT(peak, 100.0);
}

// Data side of the loop, as run_sweep_residual does it: burst detection, H1 with the burst
// left out, peaks (coherence >= 0.5 at the tops), then the two-pole modal fit of the pair.
TEST(ResidualTumFast, DataSideBurstPeaksAndSplitPair) {
  if (!has_tum()) GTEST_SKIP() << "no TUM data at " << tum_dir();
  const auto r = host::residual::read_tum_sweep(tum_dir());
  const auto b = board::load_board(std::string(amb::test::source_dir()) + "/boards/tum-mlps-rig.toml");
  const auto spans = host::residual::detect_nonlinear_spans(r.current_a, r.accel_m_s2, r.fs_hz, b.plant.amb[0].bias_current_a);
  ASSERT_FALSE(spans.empty());
  EXPECT_LT(spans.front().t0_s, 1.75);
  EXPECT_GT(spans.front().t1_s, 1.95);
  EXPECT_LT(spans.front().t1_s - spans.front().t0_s, 1.5);

  host::residual::SweepOptions o;
  for (const auto& s : spans) o.exclude_spans_s.push_back({s.t0_s, s.t1_s});
  o.zero_pad = 4;
  const auto frf = host::residual::estimate_frf(r.current_a, r.accel_m_s2, r.fs_hz, o);
  EXPECT_GT(frf.segments, 20);
  const host::residual::PeakOptions po{o.f_min_hz, o.f_max_hz, 0.5, 3.0};
  const auto peaks = host::residual::find_peaks(frf.f_hz, frf.h, frf.coherence, po);
  auto near = [&](double f) -> double {
    for (const auto& p : peaks)
      if (std::abs(p.frequency_hz / f - 1.0) < 0.03) return p.frequency_hz;
    return std::nan("");
  };
  for (double f : {100.0, 163.0, 204.0, 212.0}) EXPECT_TRUE(std::isfinite(near(f))) << "no measured peak near " << f << " Hz";
  const double p1 = near(204.0), p2 = near(212.0);
  ASSERT_TRUE(std::isfinite(p1) && std::isfinite(p2));

  // The pair as two poles common to the eight channels: two distinct, lightly damped modes
  // near the two peaks. Their shapes along the shaft are alike (one shaft bending shape split
  // in two, as an anisotropic support seen through x-y coupling or a part resonating on the
  // shaft near that frequency would split it; two different bending modes would not be).
  std::vector<std::vector<double>> w(frf.h.size());
  for (size_t c = 0; c < frf.h.size(); ++c)
    for (double g : frf.coherence[c]) w[c].push_back(std::min(g, 0.98) / (1.0 - std::min(g, 0.98)));
  const auto modes = host::residual::fit_modes(frf.f_hz, frf.h, w, 190.0, 225.0, {p1, p2});
  ASSERT_EQ(modes.size(), 2u);
  std::printf("[ RESULT ] measured pair: peaks %.2f / %.2f Hz; poles %.2f Hz (zeta %.2f %%), %.2f Hz (zeta %.2f %%), shape MAC %.3f\n",
              p1, p2, modes[0].frequency_hz, 100.0 * modes[0].damping_ratio, modes[1].frequency_hz, 100.0 * modes[1].damping_ratio,
              host::residual::mac(modes[0].shape, modes[1].shape));
  EXPECT_LT(std::abs(modes[0].frequency_hz / p1 - 1.0), 0.01);
  EXPECT_LT(std::abs(modes[1].frequency_hz / p2 - 1.0), 0.01);
  EXPECT_GT(modes[1].frequency_hz / modes[0].frequency_hz, 1.02);
  for (const auto& m : modes) {
    EXPECT_GT(m.damping_ratio, 1e-3);
    EXPECT_LT(m.damping_ratio, 0.03);
  }
  EXPECT_GT(host::residual::mac(modes[0].shape, modes[1].shape), 0.9);
}

// A generated accelerance with two close modes (known poles, residues, a residual term) and
// noise-free data: the modal fit must return the poles and the residue shapes.
TEST(ResidualTumFast, ModalFitRecoversKnownPoles) {
  const double f1 = 203.5, z1 = 0.0076, f2 = 211.8, z2 = 0.0079;
  const std::vector<cd> r1 = {{1.0, 0.1}, {0.6, -0.2}, {-0.4, 0.05}, {-0.9, 0.0}, {0.2, 0.3}};
  const std::vector<cd> r2 = {{0.3, 0.0}, {-0.8, 0.1}, {0.9, -0.1}, {0.1, 0.2}, {-0.5, 0.0}};
  std::vector<double> f;
  for (double x = 180.0; x <= 235.0; x += 0.25) f.push_back(x);
  std::vector<std::vector<cd>> h(r1.size());
  std::vector<std::vector<double>> w(r1.size(), std::vector<double>(f.size(), 1.0));
  for (size_t c = 0; c < r1.size(); ++c)
    for (double x : f) {
      const double om = 2.0 * M_PI * x, w1 = 2.0 * M_PI * f1, w2 = 2.0 * M_PI * f2;
      const cd modal = r1[c] * 1e5 / (w1 * w1 - om * om + cd(0.0, 2.0 * z1 * w1 * om)) +
                       r2[c] * 1e5 / (w2 * w2 - om * om + cd(0.0, 2.0 * z2 * w2 * om)) + cd(1e-4 * (c + 1.0), 0.0);
      h[c].push_back(-om * om * modal + cd(0.5, 0.0));
    }
  const auto m = host::residual::fit_modes(f, h, w, 185.0, 230.0, {200.0, 215.0});
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NEAR(m[0].frequency_hz, f1, 0.02);
  EXPECT_NEAR(m[1].frequency_hz, f2, 0.02);
  EXPECT_NEAR(m[0].damping_ratio, z1, 2e-4);
  EXPECT_NEAR(m[1].damping_ratio, z2, 2e-4);
  EXPECT_GT(host::residual::mac(m[0].shape, r1), 0.999);
  EXPECT_GT(host::residual::mac(m[1].shape, r2), 0.999);
  EXPECT_LT(host::residual::mac(m[0].shape, r2), 0.5);  // the shapes are told apart
}

// Eddy-current factor of solid iron, G = 1 / (1 + sqrt(j w te)): 1 without eddy currents,
// |G| = 1 / |1 + (1 + j) / sqrt(2)| with phase -22.5 deg at w te = 1, and the half-order
// asymptote (phase towards -45 deg, |G| ~ 1 / sqrt(w te)) far above the corner.
TEST(ResidualTumFast, EddyFactorIsHalfOrder) {
  model::analysis::HalfOpenBearing b;
  EXPECT_EQ(model::analysis::HalfOpenFrf::eddy_factor(b, 100.0), cd(1.0, 0.0));
  b.eddy_time_s = 3.8e-4;
  const double f_corner = 1.0 / (2.0 * M_PI * b.eddy_time_s);
  const cd g1 = model::analysis::HalfOpenFrf::eddy_factor(b, f_corner);
  EXPECT_NEAR(std::abs(g1), 1.0 / std::abs(cd(1.0 + 1.0 / std::sqrt(2.0), 1.0 / std::sqrt(2.0))), 1e-12);
  EXPECT_NEAR(std::arg(g1) * 180.0 / M_PI, -22.5, 1e-9);
  const cd g2 = model::analysis::HalfOpenFrf::eddy_factor(b, 1e4 * f_corner);
  EXPECT_NEAR(std::arg(g2) * 180.0 / M_PI, -45.0, 0.5);
  EXPECT_NEAR(std::abs(g2) * std::sqrt(1e4), 1.0, 0.02);
  EXPECT_NEAR(std::abs(model::analysis::HalfOpenFrf::eddy_factor(b, 1e-6 * f_corner)), 1.0, 2e-3);
}
