#pragma once
// Harmonic-and-sideband scoring of one defect family in an envelope spectrum, and the family
// score's null distribution measured on surrogates in the same spectrum.
//
// Normalised spectrum: each bin divided by the median of the bins within +-floor_halfwidth_hz
// (the central +-3 bins excluded). Under Gaussian noise an envelope-spectrum bin is Rayleigh
// distributed, so P(ratio > r) = 2^(-r^2) per bin. Bins within +-exclude_bins of a shaft harmonic
// k f_r (f_r refined from the record) are not searched: shaft-synchronous lines are resolved and
// set aside bin by bin instead of making a whole family "ambiguous".
//
// Family score: the lines of a template (harmonics of a base frequency and sidebands) are moved
// together by one relative offset delta in [-tolerance, +tolerance] (slip); at each delta every
// line takes the largest searchable bin within +-jitter bins of its position, its Rayleigh
// p-value over those bins, and the lines are Fisher-combined (chi-squared, 2m dof). The score is
// -log10 of the smallest combined p over delta (not corrected: the null below is measured).
//
// Null distribution: the same template evaluated at surrogate bases u x base (u in [0.55, 0.95]
// and [1.05, 1.8], steps of half a tolerance), skipping surrogates whose fundamental falls on a
// kinematic line or a defect's modulation sideband. On healthy records (bearing_check's
// calibration, docs/bearing.md) these scores are draws from the family score's null. Its upper
// tail is exponential (the -log10 of a p-value maximised over trials has a Gumbel tail) and is
// fitted from the median m and the 90th and 99th percentiles of the draws:
//   P(S > s) = 0.5 exp(-(s - m) / sigma),
//   sigma = max((q90 - m) / ln 5, (q99 - m) / ln 50, (max - m) / ln(N / 2), 1 / ln 10)
// (the largest of three tail estimates - the largest of N draws is exceeded with probability
// about 1/N - so a tail heavier than exponential widens sigma; 1/ln 10 is the scale of -log10
// of one uniform p-value).
#include <cstdint>
#include <string>
#include <vector>

#include "host-tools/core/bearing/envelope.hpp"

namespace amb::host::bearing {

/// Envelope spectrum divided by its running median, with shaft-harmonic bins marked.
struct NormalisedSpectrum {
  std::vector<double> ratio;      ///< amplitude / local median, dimensionless (bin k at k * df_hz)
  std::vector<uint8_t> excluded;  ///< 1: bin on a shaft harmonic (not searched)
  double df_hz = 0.0;             ///< bin spacing, Hz
};

/// Normalise `s` up to f_max_hz.
/// @param floor_halfwidth_hz  half width of the median window, Hz (> 0)
/// @param shaft_hz            refined shaft frequency, Hz; 0: exclude nothing
/// @param exclude_bins        bins either side of each shaft harmonic that are excluded (>= 0)
NormalisedSpectrum normalise_spectrum(const EnvelopeSpectrum& s, double f_max_hz, double floor_halfwidth_hz,
                                      double shaft_hz, int exclude_bins);

/// One line of a family template: position = multiple x base x (1 + delta) + offset_hz.
struct TemplateLine {
  double multiple = 1.0;     ///< harmonic of the base, dimensionless (> 0)
  double offset_hz = 0.0;    ///< sideband offset, Hz (+- shaft or cage frequency)
  int jitter_bins = 1;       ///< search half width around the position, bins (>= 0)
  bool fundamental = false;  ///< the family needs one fundamental present on its own
  std::string label;         ///< e.g. "1x", "2x-fr"
};

/// Result of one line at the family's best delta.
struct LineScore {
  std::string label;
  double hz = 0.0;       ///< frequency of the largest searchable bin, Hz (0: not searchable)
  double ratio = 0.0;    ///< that bin over the local median
  double p_value = 1.0;  ///< Rayleigh p-value of the line over its searchable bins
};

/// Score of a template in a normalised spectrum.
struct TemplateScore {
  double score = 0.0;     ///< -log10 of the best Fisher-combined p over delta (>= 0)
  double delta = 0.0;     ///< best relative offset of the base (slip)
  bool fundamental_present = false;  ///< a fundamental line with p < line_p on its own
  std::vector<LineScore> lines;      ///< per template line, at the best delta
};

/// Score `lines` around `base_hz` with relative search range `tolerance` (> 0).
TemplateScore score_template(const NormalisedSpectrum& s, double base_hz, const std::vector<TemplateLine>& lines,
                             double tolerance, double line_p);

/// Fitted upper tail of the family score's null.
struct NullFit {
  int samples = 0;       ///< draws the fit was made from
  double median = 0.0;   ///< median draw
  double q90 = 0.0;      ///< 90th percentile draw
  double q99 = 0.0;      ///< 99th percentile draw
  double scale = 0.0;    ///< sigma of the exponential tail
  /// log10 P(S > score) under the fitted null (<= 0; 0 if not fitted).
  double log10_p(double score) const;
  /// The score whose log10 P equals log10_p_threshold.
  double score_at(double log10_p_threshold) const;
};

/// Fit the tail from draws (fewer than 8 draws: not fitted).
NullFit fit_null(std::vector<double> draws);

/// Scores of `lines` at surrogate bases around `base_hz` (see above).
/// @param forbidden_hz  kinematic lines and sidebands: a surrogate base whose fundamental lies
///                      within tolerance (+ 2 bins) of one of them is skipped
/// @param every_line    skip a surrogate base when any of its lines (not only the fundamental)
///                      lies on a forbidden line: for a null measured on the record under test,
///                      whose defect lines must not enter it (a strong cage comb puts 3 FTF under
///                      the 2x line of the surrogate at 1.5 FTF)
std::vector<double> surrogate_scores(const NormalisedSpectrum& s, double base_hz, const std::vector<TemplateLine>& lines,
                                     double tolerance, const std::vector<double>& forbidden_hz, bool every_line = false);

}  // namespace amb::host::bearing
