// wear-id's chi-square (issue 33, third round): the film's K/C error propagated to the
// residuals, and no Birge scaling from one record's single degree of freedom.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/wearid/rig_response.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "model/journal/reynolds_fvm.hpp"

using namespace amb;
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;

namespace {
constexpr double k_deg = M_PI / 180.0;
const mj::WearParams k_wear1{mj::WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg};

// A record made by the forward model on a finer grid than the board's (so the board grid's
// fit misses it by more than the noise), at static eccentricity `eps`, 34 Hz.
wi::JournalMeasurement record(const board::BoardConfig& b, double eps) {
  board::BoardConfig fine = b;
  fine.journal.grid.cells_theta = 288;
  fine.journal.grid.cells_axial = 48;
  wi::JournalMeasurement m;
  m.speed_hz = 34.0;
  m.journal = {0.0, -eps * b.journal.geometry.clearance_m, 0.0, 0.0};
  m.eccentricity = eps;
  m.spectrum = wi::predict_spectrum(fine, k_wear1, m.journal, m.speed_hz);
  m.noise_m = 1.6e-8;
  return m;
}
}  // namespace

// The propagated sigma, recomputed here from the rig response directly (K and C from the
// board's film, each entry stepped by rel ||.||_F / 2, the residual changes in quadrature).
TEST(WearIdLevel, FilmErrorSigmaIsTheKcErrorPropagatedToTheResiduals) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  for (double eps : {0.1, 0.7}) {
    const wi::JournalMeasurement m = record(b, eps);
    wi::WearIdOptions o;
    const double rel = 2e-3;
    const std::vector<double> s = wi::film_error_sigma(b, {m}, o, k_wear1, rel);
    ASSERT_EQ(s.size(), 4u);
    mj::ReynoldsSolver solver(b.journal.geometry, k_wear1, b.journal.grid);
    const mj::DynamicCoefficients d = mj::perturbation_coefficients(solver, m.journal, 2.0 * M_PI * m.speed_hz);
    wi::RigResponse rig(b, m.speed_hz, {d.fx0_n, d.fy0_n});
    const wi::FullSpectrum z0 = rig.journal_probes(d.stiffness_n_per_m, d.damping_n_s_per_m);
    const double scale = std::sqrt(std::norm(m.spectrum.forward_m) + std::norm(m.spectrum.backward_m));
    std::vector<double> want(4, 0.0);
    for (int j = 0; j < 8; ++j) {
      Eigen::Matrix2d k = d.stiffness_n_per_m, c = d.damping_n_s_per_m;
      if (j < 4)
        k(j / 2, j % 2) += 0.5 * rel * d.stiffness_n_per_m.norm();
      else
        c((j - 4) / 2, j % 2) += 0.5 * rel * d.damping_n_s_per_m.norm();
      const wi::FullSpectrum z = rig.journal_probes(k, c);
      const std::complex<double> f = (z.forward_m - z0.forward_m) / scale, g = (z.backward_m - z0.backward_m) / scale;
      const double v[4] = {f.real(), f.imag(), g.real(), g.imag()};
      for (int i = 0; i < 4; ++i) want[static_cast<size_t>(i)] += v[i] * v[i];
    }
    double largest = 0.0;
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(s[static_cast<size_t>(i)], std::sqrt(want[static_cast<size_t>(i)]), 1e-9 * std::sqrt(want[static_cast<size_t>(i)]) + 1e-15)
          << "e " << eps << " residual " << i;
      largest = std::max(largest, s[static_cast<size_t>(i)]);
    }
    // Relative to the record's noise per real component (noise / sqrt 2 / scale).
    std::printf("e %.1f: film K/C error %.1f %% -> largest residual sigma %.3g of the spectrum, %.2f noise sigma\n", eps,
                100 * rel, largest, largest / (m.noise_m / std::sqrt(2.0) / scale));
    EXPECT_GT(largest, 0.0);
    for (double v : wi::film_error_sigma(b, {m}, o, k_wear1, 0.0)) EXPECT_EQ(v, 0.0);
  }
}

// One record: 4 residuals, 3 parameters, 1 degree of freedom. The best fit on the board's grid
// misses this record (made on a finer grid) by far more than the noise, yet chi2_min / dof
// must not scale the level (it is no estimate of the model error from one dof).
TEST(WearIdLevel, NoBirgeScalingFromOneDegreeOfFreedom) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  wi::WearIdOptions o;
  o.model = mj::WearModel::elliptical;
  o.profile_likelihood = false;
  const wi::WearIdResult r = wi::identify_wear(b, record(b, 0.1), o);
  std::printf("chi2 min %.3g, dof %d, scale %.3g, level %.3g\n", r.chi2_min, r.chi2_dof, r.chi2_scale, r.chi2_level);
  EXPECT_EQ(r.chi2_dof, 1);
  EXPECT_GT(r.chi2_min, 2.0 * r.chi2_dof);  // the case the old rule scaled
  EXPECT_EQ(r.chi2_scale, 1.0);
  EXPECT_EQ(r.chi2_film_error, 0.0);  // board grid: no refinement, no film error term
}

// Issue 33, fifth round: valleys are chosen and ranked by the chi-square the verdict uses, whose
// film-error sigma is taken at the best valley. The lowest-cost valley (0) is where the sigma is
// taken first; with it, valley 2 has the lowest chi2, so the sigma is retaken there and the
// chi2 recomputed; valley 2 stays the lowest (a fixed point): it is the best.
TEST(WearIdLevel, ValleysAreRankedByTheChi2WithTheSigmaAtTheBest) {
  std::vector<size_t> sigma_taken;
  const auto chi2_with_sigma_at = [&](size_t at) {
    sigma_taken.push_back(at);
    if (at == 0) return std::vector<double>{5.0, 9.0, 2.0, INFINITY};
    return std::vector<double>{6.0, 3.0, 1.5, INFINITY};
  };
  const wi::ValleyRanking r = wi::rank_valleys_by_chi2(4, 0, chi2_with_sigma_at);
  ASSERT_EQ(r.order.size(), 4u);
  EXPECT_EQ(r.order, (std::vector<size_t>{2, 1, 0, 3}));  // chi2 1.5, 3, 6, then the unrepresentable one
  EXPECT_EQ(r.sigma_at, 2u);
  EXPECT_TRUE(r.fixed_point);
  EXPECT_EQ(r.passes, 2);
  EXPECT_EQ(sigma_taken, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(r.chi2, (std::vector<double>{6.0, 3.0, 1.5, INFINITY}));
}

// The lowest-cost valley is already the lowest chi2: one pass. A sigma that sends the best back
// and forth stops after max_passes, not a fixed point. Bad arguments are refused.
TEST(WearIdLevel, ValleyRankingStopsAtAFixedPointOrAfterItsPasses) {
  const wi::ValleyRanking one = wi::rank_valleys_by_chi2(2, 0, [](size_t) { return std::vector<double>{1.0, 2.0}; });
  EXPECT_EQ(one.passes, 1);
  EXPECT_TRUE(one.fixed_point);
  EXPECT_EQ(one.order, (std::vector<size_t>{0, 1}));
  const wi::ValleyRanking cycle = wi::rank_valleys_by_chi2(
      2, 0, [](size_t at) { return at == 0 ? std::vector<double>{2.0, 1.0} : std::vector<double>{1.0, 2.0}; }, 3);
  EXPECT_EQ(cycle.passes, 3);
  EXPECT_FALSE(cycle.fixed_point);
  EXPECT_THROW(wi::rank_valleys_by_chi2(0, 0, [](size_t) { return std::vector<double>{}; }), std::invalid_argument);
  EXPECT_THROW(wi::rank_valleys_by_chi2(2, 2, [](size_t) { return std::vector<double>{1.0, 2.0}; }), std::invalid_argument);
  EXPECT_THROW(wi::rank_valleys_by_chi2(2, 0, [](size_t) { return std::vector<double>{1.0}; }), std::invalid_argument);
}
