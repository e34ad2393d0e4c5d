// The parts of the issue-34 hybrid on synthetic spectra whose right answer is known: the
// transported baselines (bracketing, weights, clamping, exclusion), and the correction (it is
// the baseline with no feature, recovers a known correction, vanishes for a source at the
// queried speed, and its inner cross-validation prefers the baseline when a feature is noise).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "host-tools/core/hybrid/correction.hpp"
#include "host-tools/core/hybrid/spectra.hpp"
#include "host-tools/core/hybrid/transport_base.hpp"

namespace hy = amb::host::hybrid;

namespace {

std::vector<double> centres_hz(size_t n) {
  std::vector<double> c(n);
  for (size_t k = 0; k < n; ++k) c[k] = 10.0 + 5.0 * static_cast<double>(k);
  return c;
}

hy::ReferenceSpectra ref(hy::BearingState s, double rpm, double level) {
  hy::ReferenceSpectra r;
  r.state = s;
  r.op = {rpm, 0.0};
  r.segments = 1;
  r.log_psd.assign(60, level);
  r.env_power.assign(40, level + 10.0);
  return r;
}

}  // namespace

TEST(HybridTransportBase, BracketsInterpolatesClampsAndExcludes) {
  using S = hy::BearingState;
  const std::vector<hy::ReferenceSpectra> refs = {ref(S::ball, 1700, 1.0), ref(S::ball, 1800, 3.0), ref(S::ball, 1900, 7.0),
                                                  ref(S::inner_race, 1750, 100.0)};
  const auto psd = centres_hz(60), env = centres_hz(40);
  // Flat spectra move into themselves: the interpolation is the linear mix of the levels.
  auto b = hy::transported_base(refs, S::ball, {1725.0, 0.0}, psd, env, {1.0}, 3);
  ASSERT_TRUE(b.found);
  ASSERT_EQ(b.sources.size(), 2u);
  EXPECT_NEAR(b.upper_weight, 0.25, 1e-12);
  EXPECT_NEAR(b.interp_log_psd[30], 0.75 * 1.0 + 0.25 * 3.0, 1e-9);
  EXPECT_NEAR(b.interp_env_power[20], 0.75 * 11.0 + 0.25 * 13.0, 1e-9);
  EXPECT_NEAR(b.nearest_log_psd[30], 1.0, 1e-9);
  EXPECT_EQ(b.nearest_case, "ball@1700rpm/0");
  // Outside the range: clamped to the nearest, one source of weight 1.
  b = hy::transported_base(refs, S::ball, {1950.0, 0.0}, psd, env, {1.0}, 3);
  ASSERT_EQ(b.sources.size(), 1u);
  EXPECT_DOUBLE_EQ(b.sources[0].weight, 1.0);
  EXPECT_NEAR(b.interp_log_psd[30], 7.0, 1e-9);
  // Excluding the operating point of the query (cross-fitting): 1800 is bracketed by 1700 and 1900.
  const hy::OperatingPoint at1800{1800.0, 0.0};
  b = hy::transported_base(refs, S::ball, at1800, psd, env, {1.0}, 3, &at1800);
  ASSERT_EQ(b.sources.size(), 2u);
  EXPECT_NEAR(b.interp_log_psd[30], 0.5 * 1.0 + 0.5 * 7.0, 1e-9);
  // A state without a training case: nothing.
  EXPECT_FALSE(hy::transported_base(refs, S::outer_race, at1800, psd, env, {1.0}, 3).found);
  // all_sources: every other case of the state, weight 1 each.
  EXPECT_EQ(hy::all_sources(refs, S::ball, at1800, psd, env, {1.0}, 3, at1800).size(), 2u);
}

namespace {

// Cases whose measured spectrum is the base plus 0.6 x the fixed-frequency lines (the feature
// fixed_lines), with small noise; each case its own random base and fixed lines.
std::vector<hy::CorrectionCase> synthetic_cases(int groups, int per_group, double gain, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<hy::CorrectionCase> out;
  const size_t bins = 120;
  for (int gr = 0; gr < groups; ++gr)
    for (int i = 0; i < per_group; ++i) {
      hy::CorrectionCase c;
      c.group = gr;
      c.speed_change = 0.03;
      c.base.resize(bins);
      c.fixed.resize(bins);
      c.sim.resize(bins);
      for (size_t k = 0; k < bins; ++k) {
        c.base[k] = -5.0 + 0.01 * static_cast<double>(k) + g(rng);
        c.fixed[k] = g(rng);
        c.sim[k] = g(rng);
      }
      const auto lf = hy::local_mean(c.fixed, 3);
      for (int s = 0; s < 3; ++s) {
        std::vector<double> y(bins);
        for (size_t k = 0; k < bins; ++k) y[k] = c.base[k] + gain * (c.fixed[k] - lf[k]) + 0.05 * g(rng);
        c.segments.push_back(y);
      }
      out.push_back(std::move(c));
    }
  return out;
}

}  // namespace

TEST(HybridCorrection, NoFeatureIsTheBaselineAndAKnownCorrectionIsRecovered) {
  const auto train = synthetic_cases(2, 3, 0.6, 1), test = synthetic_cases(1, 1, 0.6, 2);
  hy::CorrectionOptions none;
  none.features = 0;
  hy::Correction c0;
  c0.train(train, none);
  EXPECT_EQ(c0.predict(test[0]), test[0].base);

  hy::CorrectionOptions o;
  o.features = 0b00100;  // fixed_lines
  o.bands = 1;
  o.lambda = 1e-6;
  hy::Correction c;
  c.train(train, o);
  const auto y = c.predict(test[0]);
  const auto lf = hy::local_mean(test[0].fixed, 3);
  double err = 0, ref = 0;
  for (size_t k = 0; k < y.size(); ++k) {
    const double truth = test[0].base[k] + 0.6 * (test[0].fixed[k] - lf[k]);
    err += (y[k] - truth) * (y[k] - truth);
    ref += (test[0].base[k] - truth) * (test[0].base[k] - truth);
  }
  EXPECT_LT(err, 0.01 * ref) << "the known correction was not recovered";
  // A source at the queried speed needs no correction; half the training change gives half.
  auto at_speed = test[0];
  at_speed.speed_change = 0.0;
  EXPECT_EQ(c.predict(at_speed), test[0].base);
  auto half = test[0];
  half.speed_change = 0.015;
  const auto yh = c.predict(half);
  for (size_t k = 0; k < y.size(); k += 17) EXPECT_NEAR(yh[k] - half.base[k], 0.5 * (y[k] - test[0].base[k]), 1e-9);
  // Beyond the largest training change the correction is not extrapolated.
  auto far = test[0];
  far.speed_change = 0.3;
  EXPECT_EQ(c.predict(far), y);
  // Model file round trip.
  const auto back = hy::Correction::from_json(c.to_json());
  EXPECT_EQ(back.predict(test[0]), y);
}

TEST(HybridCorrection, InnerCrossValidationFindsTheRealFeatureAndKeepsTheBaselineWithoutOne) {
  const auto cand = hy::correction_candidates(3, 16);
  // A real fixed-lines effect: chosen, with fixed_lines among the features, above the baseline.
  auto cv = hy::select_correction(synthetic_cases(2, 3, 0.6, 3), cand);
  EXPECT_NE(cv.chosen.features & 0b00100u, 0u) << cv.chosen.describe();
  EXPECT_GT(cv.chosen_pearson, cv.baseline_pearson + 0.01);
  // No effect at all (measured = base + noise): nothing beats the baseline by more than noise.
  cv = hy::select_correction(synthetic_cases(2, 3, 0.0, 4), cand);
  EXPECT_LT(cv.chosen_pearson - cv.baseline_pearson, 1e-3) << cv.chosen.describe();
  // One operating point only: refused, naming why.
  EXPECT_THROW(hy::select_correction(synthetic_cases(1, 3, 0.6, 5), cand), std::invalid_argument);
}

TEST(HybridCorrection, EnsembleBandHoldsThePredictionAndIsReproducible) {
  const auto train = synthetic_cases(2, 3, 0.6, 6), test = synthetic_cases(1, 1, 0.6, 7);
  hy::CorrectionEnsemble a, b;
  a.train(train, hy::correction_candidates(3, 16), 8, 11);
  b.train(train, hy::correction_candidates(3, 16), 8, 11);
  EXPECT_EQ(a.members.size(), 2u + 8u) << "two leave-one-point-out fits and eight bootstrap fits";
  std::vector<double> y, lo, hi, y2, lo2, hi2;
  a.predict({test[0]}, {1.0}, y, lo, hi);
  b.predict({test[0]}, {1.0}, y2, lo2, hi2);
  EXPECT_EQ(y, y2);
  EXPECT_EQ(lo, lo2);
  EXPECT_EQ(hi, hi2);
  for (size_t k = 0; k < y.size(); ++k) {
    EXPECT_LE(lo[k], y[k]);
    EXPECT_GE(hi[k], y[k]);
  }
  EXPECT_EQ(a.to_json(), hy::CorrectionEnsemble::from_json(a.to_json()).to_json());
}
