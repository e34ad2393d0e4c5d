#pragma once
// bearing-check: envelope analysis of a measured vibration record against the kinematic defect
// frequencies of a named bearing, with a statistical "stands out" test and a verdict.
//
// "Stands out": in the envelope spectrum, the largest bin inside the search window around
// h * f_pred (half width = (speed uncertainty + slip allowance) * h * f_pred, at least 2 bins)
// exceeds k times the median of the surrounding floor window (the search window excluded).
// Under Gaussian noise the envelope-spectrum amplitude is Rayleigh distributed, for which
// P(A > k * median) = 2^(-k^2); k is set so that the probability of a false line anywhere
// in the search window is false_alarm_probability: k = sqrt(log2(n_window / p_fa)).
//
// Verdict rule (see docs/bearing.md):
//  - a family (BPFO, BPFI, ball) has evidence if its fundamental stands out (ball: BSF or 2*BSF,
//    as a ball defect strikes both races per spin) and at least one further harmonic
//    (or, for the inner race, a shaft-frequency sideband of the fundamental) also stands out;
//  - score = sum over standing-out lines of log2(ratio / k);
//  - a line whose search window overlaps a window of another family's harmonic or of a shaft
//    harmonic k*f_r is ambiguous (e.g. 3*BPFO ~ 2*BPFI for 6205) and counts for nobody;
//  - no family with evidence -> "healthy" (an FTF line alone -> "unclear");
//    one family, or one whose score is >= 2x every other -> that family; otherwise "unclear";
//  - dominance: a localised defect drives the band envelope, so its family must be stronger
//    than the shaft-synchronous family (geometric mean of the peak/floor ratios of harmonics
//    1..3). If shaft-rate modulation (unbalance, looseness, misalignment) is as strong as the
//    defect lines, the evidence is "unclear";
//  - impulsiveness: a localised defect makes the resonance band impulsive. The spectral
//    kurtosis of the selected band is 0 for Gaussian noise and -1 for a pure tone; a fault
//    verdict needs SK >= min_band_kurtosis (1.0), otherwise standing-out lines are "unclear"
//    (periodic but not impulsive modulation is not evidence of a localised defect).
#include <optional>
#include <string>
#include <vector>

#include "host-tools/core/bearing/envelope.hpp"
#include "model/bearing/geometry.hpp"

namespace amb::host::bearing {

/// Options of bearing_check (defaults documented in docs/bearing.md).
struct BearingCheckOptions {
  double speed_uncertainty = 0.005;       ///< relative uncertainty of the given speed (CWRU: +-0.5 %)
  double slip_allowance = 0.01;           ///< extra relative tolerance for rolling-element slip
  double false_alarm_probability = 1e-3;  ///< per search window, under Rayleigh noise
  int harmonics = 2;                      ///< harmonics examined per family (>= 2); with 3, lines of
                                          ///< different families coincide (6205: 3 BPFO ~ 2 BPFI, 3 BSF ~ 2 BPFO)
  double min_band_kurtosis = 1.0;         ///< a fault verdict needs an impulsive band (see below)
  double floor_halfwidth_hz = 0.0;        ///< floor window half width, Hz; 0: 10x the search half width, >= 5 Hz
  bool remove_discrete = false;           ///< edit discrete spectral lines out before band selection (off:
                                          ///< CWRU race faults are themselves near-discrete; docs/bearing.md)
  double discrete_halfwidth_hz = 5.0;     ///< median window half width of the discrete-line test, Hz
  int strongest_lines = 12;               ///< how many of the strongest envelope lines to report (0: none)
  BandSelectionOptions band;              ///< band grid; min_bandwidth_hz is raised to max(4, harmonics+2)*BPFI
  bool valid() const;
};

/// A line of the envelope spectrum that stands out of its local floor (for the analyst).
struct EnvelopeLine {
  double hz = 0.0;     ///< frequency, Hz
  double ratio = 0.0;  ///< amplitude / median of the bins within +-floor window (line excluded)
};

/// One searched line.
struct LineResult {
  double predicted_hz = 0.0;           ///< kinematic prediction, Hz
  std::optional<double> found_hz;      ///< frequency of the peak if it stands out, Hz
  double peak_hz = 0.0;                ///< largest bin in the window whether it stands out or not, Hz
  double ratio = 0.0;                  ///< peak / local median floor, dimensionless
  double threshold = 0.0;              ///< k, dimensionless
  bool ambiguous = false;              ///< window overlaps another family's or a shaft harmonic's
  bool stands_out() const { return found_hz.has_value(); }
  /// Counts as evidence: stands out and is not ambiguous.
  bool counts() const { return stands_out() && !ambiguous; }
};

/// Result of one family (fundamental and harmonics).
struct FamilyResult {
  std::vector<LineResult> harmonics;  ///< index 0: fundamental
  bool evidence = false;              ///< see the verdict rule
  double score = 0.0;                 ///< sum of log2(ratio / k) over counting lines
  double strength = 0.0;              ///< geometric mean of the harmonics' peak/floor ratios
};

/// Everything bearing-check computed.
struct BearingCheckResult {
  model::bearing::DefectFrequencies predicted;  ///< kinematic frequencies at the given speed
  FamilyResult bpfo, bpfi, ftf;
  FamilyResult bsf;       ///< ball spin family: lines at BSF and its harmonics
  FamilyResult bsf2;      ///< ball defect family: lines at 2*BSF and its harmonics
  FamilyResult shaft;     ///< shaft-synchronous family k * f_r (reference for dominance)
  LineResult bpfi_lower_sideband;  ///< BPFI - shaft frequency
  LineResult bpfi_upper_sideband;  ///< BPFI + shaft frequency
  std::optional<double> found_bsf_hz;  ///< BSF line, or half the 2*BSF line, if one stands out
  Band band;                           ///< resonance band used
  DiscreteRemoval discrete;            ///< what the discrete-line removal did (zero if off)
  /// Strongest local maxima of the envelope spectrum between 1 Hz and 2 BPFI + 2 f_r whose
  /// ratio exceeds k = sqrt(log2(n_bins / p_fa)) (false-alarm-corrected for all bins searched),
  /// strongest first, at most options.strongest_lines.
  std::vector<EnvelopeLine> strongest_lines;
  std::string verdict;                 ///< outer_race, inner_race, ball, healthy, unclear
  std::string reason;                  ///< one sentence saying why
};

/// Run the check. Throws std::invalid_argument on bad input (fs <= 0, speed <= 0, short record,
/// invalid geometry or options).
/// @param x               vibration record (acceleration, any unit)
/// @param fs_hz           sample rate, Hz
/// @param shaft_speed_hz  nominal shaft speed, Hz
BearingCheckResult check_bearing(const std::vector<double>& x, double fs_hz, double shaft_speed_hz,
                                 const model::bearing::BearingGeometry& g,
                                 const BearingCheckOptions& o = {});

/// Search one line in an envelope spectrum (exposed for tests and the model check).
LineResult find_line(const EnvelopeSpectrum& s, double predicted_hz, double rel_tolerance,
                     const BearingCheckOptions& o);

}  // namespace amb::host::bearing
