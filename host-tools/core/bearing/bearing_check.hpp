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
// Decision (issue 15, see docs/bearing.md "Decision"):
//  - bands: every band of the kurtogram grid (dyadic + 1/3-dyadic, 50 % overlap, narrowest
//    max(4, harmonics + 2) x BPFI) that passes the guards: not in the top 15 % below Nyquist
//    (anti-alias roll-off and converter artefacts), not tonal (SK significantly below 0: its
//    envelope is a beat of a few tones). The band is chosen per family by the evidence it
//    carries (protrugram-style: the envelope-spectrum lines, not the envelope's kurtosis), so a
//    band of a few isolated spikes with SK 4900 cannot capture the selection;
//  - family significance (line_family.hpp): Fisher combination of the Rayleigh p-values of the
//    fundamental, harmonics and (inner race: +-f_r, ball: 2 BSF +- FTF) sidebands, searched
//    jointly over the kinematic tolerance, Bonferroni-corrected for the fundamental positions,
//    the bands and the families tried; detected if p_corrected < family_false_alarm AND a
//    fundamental and at least one further line are present on their own (p < line_p);
//  - explained away: a line of a weaker family that sits on a line of the stronger detected
//    family's pattern (harmonics, their +-1..3 f_r sidebands for the inner race, +-1..2 FTF for
//    the ball) is that family's, not evidence for the weaker one;
//  - relative strength: of two detected families the stronger wins if its significance is
//    >= dominance x the other's or its strongest fundamental is >= dominance x as far above
//    the floor; otherwise "unclear" (evidence truly split);
//  - impulsiveness: only bands with SK > impulsive_sigmas x its Gaussian standard error can carry
//    a defect verdict; a family significant only in non-impulsive bands makes the record
//    "unclear" (periodic modulation without impacts);
//  - cage comb: when the cage family (n x FTF) is significant, inner-race and ball lines that sit
//    on one of its teeth are the comb's (6205: BSF ~ 6 FTF, 2 BSF ~ 12 FTF, BPFI +- f_r ~ 11, 16
//    FTF); the outer race is exempt (BPFO = Z x FTF by kinematics);
//    an outer-race verdict needs BPFO >= dominance x the cage teeth next to it (Z-2..Z+2 FTF)
//    and x the comb's first teeth (1..3 FTF),
//    else "unclear" (a cage-modulated comb, e.g. a ball fault, also has a tooth on BPFO);
//  - no detected defect family -> "healthy"; only the cage (FTF) family -> "unclear".
#include <optional>
#include <string>
#include <vector>

#include "host-tools/core/bearing/envelope.hpp"
#include "host-tools/core/bearing/line_family.hpp"
#include "model/bearing/geometry.hpp"

namespace amb::host::bearing {

/// Options of bearing_check (defaults documented in docs/bearing.md).
struct BearingCheckOptions {
  double speed_uncertainty = 0.005;       ///< relative uncertainty of the given speed (CWRU: +-0.5 %)
  double slip_allowance = 0.01;           ///< extra relative tolerance for rolling-element slip
  double false_alarm_probability = 1e-3;  ///< per search window, under Rayleigh noise
  int harmonics = 3;                      ///< harmonics examined per family (>= 2); lines of different
                                          ///< families that coincide (6205: 3 BPFO ~ 2 BPFI) count for none
  double min_band_kurtosis = 1.0;         ///< legacy, unused by the decision (kept for API compatibility)
  /// Family-wise false-alarm probability of one record: the chance that noise alone makes any
  /// defect family "detected" in any band tried (Rayleigh floor model). (0, 1)
  double family_false_alarm = 1e-3;
  double line_p = 0.01;                   ///< a line is present on its own if its p-value < line_p
  double dominance = 2.0;                 ///< relative strength needed to name one of two detected families
  /// A defect verdict needs an impulsive band: spectral kurtosis above impulsive_sigmas x its
  /// standard error under Gaussian noise (a localised defect strikes; periodic lines in a
  /// Gaussian band are modulation, not impacts). >= 0
  double impulsive_sigmas = 3.0;
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
  std::vector<LineResult> harmonics;  ///< index 0: fundamental (in the family's band, for display)
  bool evidence = false;              ///< detected (see the decision rule)
  double score = 0.0;                 ///< significance: -log10 of the corrected family p-value
  double strength = 0.0;              ///< peak/floor ratio of the strongest present fundamental line
  FamilyTest test;                    ///< the family test in its best band
  std::vector<std::string> line_labels;  ///< label of each line of `test`
  Band band;                          ///< the band where this family's evidence is strongest
  double log10_p_corrected = 0.0;     ///< log10 p after correction for positions, bands, families
  int explained_lines = 0;            ///< lines attributed to a stronger family's pattern or the cage comb
  bool significant_without_impacts = false;  ///< detected only in bands that are not impulsive
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
  Band band;                           ///< resonance band of the verdict (winning or most significant family)
  size_t bands_tried = 0;              ///< bands that passed the guards
  bool outer_in_cage_comb = false;     ///< BPFO lines not above the neighbouring cage-comb teeth
  double cage_teeth_ratio = 0.0;       ///< strongest cage tooth (1..3 and Z-2..Z+2 x FTF) over its floor
  double log10_tests = 0.0;            ///< log10 of the Bonferroni factor for bands x families
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
