#pragma once
// Significance of a family of envelope-spectrum lines (a defect fundamental, its harmonics and,
// where the physics puts them, its sidebands) against the local floor, with a stated
// false-alarm probability.
//
// Noise model: in a band of Gaussian noise the envelope-spectrum amplitude of one bin is
// Rayleigh distributed, so P(A > r * median) = 2^(-r^2). A line searched over n bins therefore
// has the p-value p = 1 - (1 - 2^(-r^2))^n, r = largest bin / median of the floor window.
// The lines of one family are combined by Fisher's method: X = -2 sum ln p_i is chi-squared
// with 2m degrees of freedom under noise. The family's harmonics are exact multiples of one
// (unknown) fundamental, so the fundamental is searched on a grid of relative offsets
// delta in [-tolerance, +tolerance] (speed uncertainty + slip) with all lines moved together;
// the smallest p over delta is multiplied by the number of independent fundamental positions
// tried (Bonferroni). bearing_check multiplies further by the number of bands and families.
#include <string>
#include <vector>

#include "host-tools/core/bearing/envelope.hpp"

namespace amb::host::bearing {

/// One expected line of a family: position = multiple * f_base * (1 + delta) + offset_hz.
struct FamilyLine {
  double multiple = 1.0;     ///< harmonic of the base frequency, dimensionless (> 0)
  double offset_hz = 0.0;    ///< sideband offset, Hz (e.g. +- shaft or cage frequency)
  double offset_uncertainty = 0.0;  ///< relative uncertainty of offset_hz (e.g. speed uncertainty)
  bool fundamental = false;  ///< a fundamental: the family needs one of these present
  bool ambiguous = false;    ///< shares its position with another family: not evidence (set by the caller)
  std::string label;         ///< e.g. "2x", "1x-fr"
};

/// Result of one line at the best delta.
struct FamilyLineResult {
  double hz = 0.0;        ///< frequency of the largest bin in the line's search range, Hz
  double ratio = 0.0;     ///< that bin / median of the floor window
  double p_value = 1.0;   ///< Rayleigh p-value of the line over its search range (1 if ambiguous)
  bool ambiguous = false;
};

/// Result of a family test in one envelope spectrum.
struct FamilyTest {
  double base_hz = 0.0;           ///< nominal base frequency, Hz
  double delta = 0.0;             ///< best relative offset of the fundamental
  double log10_p = 0.0;           ///< log10 of the family p-value after the delta correction (<= 0)
  double trials = 1.0;            ///< independent fundamental positions tried (the delta correction)
  int lines_present = 0;          ///< counting lines with p < line_p
  bool fundamental_present = false;  ///< a fundamental line with p < line_p
  std::vector<FamilyLineResult> lines;  ///< per FamilyLine, at the best delta
};

/// Settings of the family test.
struct FamilyTestOptions {
  double tolerance = 0.015;     ///< relative search range of the fundamental (speed + slip), > 0
  double line_p = 0.01;         ///< a line is "present" if its own p-value is below this
  double floor_halfwidth_hz = 0.0;  ///< floor window half width, Hz; 0: max(10 x the line's search half width, 5 Hz)
  /// Shaft frequency, Hz (0: no check). At each delta, a line whose position lies within
  /// (its search range + shaft_tolerance x k f_r) of a shaft harmonic k f_r (k <= 64) is
  /// ambiguous there (shaft-synchronous modulation, not the defect) and is not counted.
  double shaft_hz = 0.0;
  double shaft_tolerance = 0.005;  ///< relative uncertainty of shaft_hz
};

/// log of the chi-squared survival function with 2m degrees of freedom at x (exact for even dof).
double log_chi2_sf_even(double x, int m);

/// Test one family in an envelope spectrum. Lines outside the spectrum count as absent (p = 1).
FamilyTest test_family(const EnvelopeSpectrum& s, double base_hz, const std::vector<FamilyLine>& lines,
                       const FamilyTestOptions& o);

}  // namespace amb::host::bearing
