// Enhanced envelope spectrum (host-tools/core/bearing/enhanced_envelope.hpp): the Gamma tail,
// its calibration on Gaussian noise, and the gain over one band on a modulation spread thinly
// over a broad band.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "host-tools/core/bearing/enhanced_envelope.hpp"
#include "host-tools/core/bearing/family_score.hpp"

namespace hb = amb::host::bearing;

TEST(EnhancedEnvelope, GammaTailMatchesTheClosedForms) {
  for (double t : {0.1, 1.0, 7.5, 40.0}) {
    EXPECT_NEAR(hb::log2_gamma_tail(t, 1), -t / std::log(2.0), 1e-9) << t;                        // e^-t
    EXPECT_NEAR(hb::log2_gamma_tail(t, 2), std::log2(std::exp(-t) * (1 + t)), 1e-9) << t;          // e^-t (1 + t)
    EXPECT_NEAR(hb::log2_gamma_tail(t, 3), std::log2(std::exp(-t) * (1 + t + t * t / 2)), 1e-9) << t;
  }
  // A strong line: no overflow, and the tail is monotone in t and in m.
  const double a = hb::log2_gamma_tail(2000.0, 24), b = hb::log2_gamma_tail(2100.0, 24), c = hb::log2_gamma_tail(2000.0, 30);
  EXPECT_TRUE(std::isfinite(a));
  EXPECT_LT(b, a);
  EXPECT_GT(c, a);
  EXPECT_EQ(hb::log2_gamma_tail(0.0, 5), 0.0);
}

TEST(EnhancedEnvelope, BandsAreDisjointAndInsideTheRange) {
  const auto b = hb::ees_bands(500.0, 4700.0, 800.0);
  ASSERT_EQ(b.size(), 5u);
  for (size_t i = 0; i < b.size(); ++i) {
    EXPECT_DOUBLE_EQ(b[i].high_hz - b[i].low_hz, 800.0);
    if (i > 0) {
      EXPECT_DOUBLE_EQ(b[i].low_hz, b[i - 1].high_hz);
    }
  }
  EXPECT_LE(b.back().high_hz, 4700.0);
  EXPECT_TRUE(hb::ees_bands(500.0, 1000.0, 800.0).empty());
}

namespace {
std::vector<double> noise(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> x(n);
  for (auto& v : x) v = g(rng);
  return x;
}
}  // namespace

// On Gaussian noise the EES bin has the single-band tail P(r > x) = 2^-x^2 (that is what the
// family scores and their nulls assume). A plain average of the bands' squared ratios would not:
// its tail is much lighter (P(r > 2) ~ 1e-4 for 5 bands instead of 1/16).
TEST(EnhancedEnvelope, NoiseBinsHaveTheSingleBandTail) {
  const double fs = 12000.0;
  const auto x = noise(static_cast<size_t>(20 * fs), 7);
  const hb::BandAnalyser a(x, fs);
  const auto bands = hb::ees_bands(600.0, 4600.0, 800.0);
  ASSERT_EQ(bands.size(), 5u);
  const auto ees = hb::enhanced_envelope_spectrum(a, bands, 420.0, 5.0);
  const auto ns = hb::normalise_spectrum(ees, 400.0, 5.0, 0.0, 0);
  size_t n = 0, above1 = 0, above2 = 0;
  for (size_t k = 40; k < ns.ratio.size(); ++k) {  // above 2 Hz
    ++n;
    above1 += ns.ratio[k] > 1.0 ? 1 : 0;
    above2 += ns.ratio[k] > 2.0 ? 1 : 0;
  }
  ASSERT_GT(n, 7000u);
  // Expected 1/2 and 1/16. Neighbouring bins are correlated (Hann), so the binomial standard
  // error is widened by 2; the bands are 5 sigma apart.
  const double f1 = double(above1) / double(n), f2 = double(above2) / double(n);
  EXPECT_NEAR(f1, 0.5, 5 * 2 * std::sqrt(0.25 / double(n)));
  EXPECT_NEAR(f2, 1.0 / 16.0, 5 * 2 * std::sqrt(0.0586 / double(n)));
}

// A 3 % amplitude modulation of broadband noise at 13 Hz, too weak to be significant in any one
// band (the best of five: 3.9x its floor, P ~ 2 % over the 800 bins searched): the EES over the
// five bands holds it at 5.9x (P ~ 2^-35 per bin).
TEST(EnhancedEnvelope, AddsUpAModulationSpreadOverTheBands) {
  const double fs = 12000.0, f_mod = 13.0;
  auto x = noise(static_cast<size_t>(10 * fs), 11);
  for (size_t i = 0; i < x.size(); ++i) x[i] *= 1.0 + 0.03 * std::cos(2 * M_PI * f_mod * double(i) / fs);
  const hb::BandAnalyser a(x, fs);
  const auto bands = hb::ees_bands(600.0, 4600.0, 800.0);
  auto line = [&](const hb::EnvelopeSpectrum& s) {
    const auto ns = hb::normalise_spectrum(s, 60.0, 5.0, 0.0, 0);
    const long c = std::lround(f_mod / ns.df_hz);
    double m = 0.0;
    for (long k = c - 1; k <= c + 1; ++k) m = std::max(m, ns.ratio[static_cast<size_t>(k)]);
    return m;
  };
  double best_single = 0.0;
  for (const auto& b : bands) best_single = std::max(best_single, line(a.envelope_spectrum(b)));
  const double ees = line(hb::enhanced_envelope_spectrum(a, bands, 80.0, 5.0));
  EXPECT_GT(ees, best_single) << "single " << best_single << " ees " << ees;
  EXPECT_LT(best_single, 4.5);  // the setup: no single band reaches that level (3.9 here)
  EXPECT_GT(ees, 4.5) << "single " << best_single;
}
