#pragma once
// bearing-check: rolling-bearing diagnosis of a vibration record to the standard of Smith &
// Randall's CWRU benchmark (MSSP 2015), one procedure for every record (docs/bearing.md):
//   1. pre-whitening: cepstrum pre-whitening (CPW: unit magnitude, phase kept);
//   2. band selection by spectral kurtosis: the kurtogram grid (dyadic + 1/3-dyadic, 50 %
//      overlap) on the whitened and on the raw signal, guarded against the anti-alias top of
//      the spectrum and tonal bands; three analysis bands: the whole whitened band, the
//      whitened kurtogram maximum, the raw kurtogram maximum;
//   3. envelope spectrum of each band (squared envelope, Hann);
//   4. harmonic + sideband scoring per family (family_score.hpp): BPFO (3 harmonics); BPFI
//      (3 harmonics, 1x and 2x with +-f_r sidebands); ball (2 BSF as fundamental, BSF, 4 BSF,
//      2 BSF +- FTF);
//      cage (3 harmonics of FTF); bins on shaft harmonics of the refined speed are set aside;
//   5. the shaft speed refined from the record's shaft-harmonic comb within +-2 % of nominal
//      (speed_refine.hpp), in the spectrum or else in the whitened envelope spectrum; family
//      bases move jointly by +-slip_tolerance (+ speed_range when the speed is not refined);
//   6. decision: each family's score against its null distribution, measured on healthy records
//      (scores of the family's template at surrogate bases, fitted tail; family_score.hpp and
//      docs/bearing.md "Calibration"); detected if P_null < record_false_alarm / (bands x
//      families) and its fundamental is present on its own; of several detected families the
//      one with the smallest P_null on lines no other detected family found is named; the
//      others carry the reason they were not; the cage family alone is a ball fault seen through
//      its cage modulation, and a record with nothing detected is scanned for that modulation in
//      the raw signal with the record's own surrogate null (cage_modulation_as_ball, raw_cage_scan;
//      off by default: healthy bearings with ball-size variation set it off).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "host-tools/core/bearing/envelope.hpp"
#include "host-tools/core/bearing/family_score.hpp"
#include "host-tools/core/bearing/speed_refine.hpp"
#include "model/bearing/geometry.hpp"

namespace amb::host::bearing {

/// Options of bearing_check (defaults documented in docs/bearing.md).
struct BearingCheckOptions {
  double slip_tolerance = 0.015;   ///< relative search range of each family's base (rolling slip 1-2 %), (0, 0.1]
  double speed_range = 0.02;       ///< relative range of the speed refinement around nominal, (0, 0.2]
  int harmonics = 3;               ///< harmonics of BPFO, BPFI and FTF scored (>= 2)
  /// Record-wise false-alarm probability: the chance that a healthy record has any family
  /// detected in any band, split evenly (Bonferroni) over bands x families. (0, 1)
  double record_false_alarm = 0.01;
  double line_p = 0.01;            ///< a fundamental is present on its own if its p-value < line_p, (0, 1)
  double floor_halfwidth_hz = 5.0; ///< envelope-spectrum floor window half width, Hz (> 0)
  int shaft_exclude_bins = 2;      ///< bins either side of a shaft harmonic set aside (>= 0)
  /// BPFO = Z x FTF by kinematics, so cage modulation (a ball going round with the cage, or the
  /// cage) also puts a line on BPFO. When the comb is there (cage family detected, or one of
  /// its teeth 1..3 and Z-2..Z+2 x FTF present on its own), an outer-race verdict needs the BPFO
  /// line >= comb_dominance x the strongest of those teeth, in BPFO's band and in the cage
  /// family's best band; otherwise BPFO is a tooth of the comb. >= 1
  double comb_dominance = 2.0;
  /// A ball fault's impacts are modulated at FTF (the ball goes round with the cage through
  /// the load zone; Smith & Randall 2015 score balls with FTF sidebands), so its envelope
  /// carries the cage family's lines too, often stronger than its own 2 x BSF lines. When on and
  /// the ball family is detected on lines of its own, the cage family is that modulation and
  /// does not compete for the verdict (without it such records are `unclear`: "only the cage
  /// family"). docs/bearing.md, model-made ball records.
  bool cage_as_ball_modulation = true;
  /// Cage-rate modulation alone read as a ball fault (issue 32; docs/bearing.md "Ball faults seen
  /// through the cage"). A ball defect goes round with the cage through the load zone, so its
  /// impacts are amplitude-modulated at FTF; where its own 2 x BSF lines are weak (the ball's spin
  /// axis wanders, so the spot does not strike at every spin) the envelope holds the cage family
  /// alone. When on:
  ///  (a) the cage family detected without a race or ball family of its own names `ball`
  ///      (off: `unclear`);
  ///  (b) only with raw_cage_scan on (off by default, below): a record with no family detected
  ///      is scanned for the cage family in the RAW signal's
  ///      envelope over the two narrowest levels of the kurtogram grid, tonal bands included: the
  ///      modulation of a discrete carrier is itself discrete, so CPW flattens it and discrete
  ///      removal edits it out. Raw envelopes hold the beats of the record's own tones (the
  ///      CWRU healthy record: surrogate scores up to 70 in its tonal 3-5 kHz bands, none in the
  ///      model-made records), so the scan's null is the record's own: the cage template at
  ///      surrogate bases in every scanned band, tail fitted as for the calibrated nulls. Its
  ///      record-wise false-alarm budget is its own (record_false_alarm split over the bands
  ///      scanned), so a healthy record's chance of any verdict is at most 2 x record_false_alarm.
  /// A cage fault gives the same lines: the checker does not tell it from a ball fault, nor from
  /// a healthy bearing's ball-size variation (one ball larger than the others loads more as it
  /// goes round with the cage). Measured for (a) alone on healthy model records with one ball
  /// 0.25-1 um oversized (docs/bearing.md "Healthy bearings with ball-size variation"): 3 of 396
  /// named ball.
  bool cage_modulation_as_ball = true;
  /// Rule (b) of cage_modulation_as_ball, the raw-signal cage scan. Off: on healthy model records
  /// with one ball 0.25-1 um oversized (ISO 3290 lot diameter variation of grades G10-G28) it
  /// names 27 of 396 `ball` (6.8 %, above the 2 % false-alarm bound): the oversized ball
  /// modulates the bearing's own discrete lines at FTF, which is exactly what the scan looks
  /// for. With it off 1750_B_7_DE12 is not diagnosed (docs/bearing.md).
  bool raw_cage_scan = false;
  int raw_cage_min_surrogates = 200;  ///< fewer surrogate draws in the scan: no raw verdict (>= 8)
  double false_alarm_probability = 1e-3;  ///< per search window of find_line (display lines)
  BandSelectionOptions band;       ///< kurtogram grid; min_bandwidth_hz raised to (harmonics + 2) x BPFI
  /// Also analyse the raw signal's kurtogram band (S&R's un-whitened baseline). Off: in the raw
  /// band discrete lines and cage modulation put race lines where there is no race defect
  /// (docs/bearing.md, leave-one-out).
  bool raw_sk_band = false;
  /// Also analyse the kurtogram band of the raw signal with its discrete components removed
  /// (BandAnalyser::remove_discrete_components: spectral editing of the lines that stand out of
  /// their local median, S&R's second pre-whitening route, discrete/random separation, in its
  /// spectral-editing form). Unlike CPW it keeps the spectrum's colouring, so a resonance band
  /// that the fault's impacts excite keeps its signal-to-noise ratio. Off: measured on the
  /// model-made records (docs/bearing.md) it finds one more outer-race fault (61/64) but names
  /// outer_race on 3 of 99 healthy records (the healthy bearing's ball-pass compliance lines,
  /// spread over several bins by the speed jitter, survive the editing in a resonance band).
  bool discrete_removed_band = false;
  /// Also analyse the enhanced envelope spectrum of the whitened signal (enhanced_envelope.hpp):
  /// the envelope spectra of disjoint bands of the kurtogram's narrowest width, from its lowest
  /// edge to the guard, each over its own floor, combined with the exact Gamma tail. A fault's
  /// modulation spread thinly over a broad resonance adds up over the bands where no single
  /// band holds enough of it. A third band in the Bonferroni split. Off: measured
  /// (docs/bearing.md, "Enhanced envelope spectrum"), it names the CWRU healthy record `ball` at
  /// its native 48 kHz (24 bands: the healthy bearing's own cage line at 12.05 Hz, 5.8x its
  /// floor; the 7-mil ball record 1797_B's is 5.6x at 12 kHz) and widens the measured null (FTF
  /// threshold 5.22 -> 5.90): summed over enough bands, a healthy bearing's benign kinematic
  /// modulation is itself significant against the noise null.
  bool enhanced_envelope_band = false;
  double discrete_halfwidth_hz = 5.0;      ///< median window half width of the discrete removal, Hz (> 0)
  double discrete_false_alarm = 1e-3;      ///< bins edited by chance per record under Gaussian noise, (0, 1)
  /// Null of each family's score (bpfo, bpfi, ball, ftf), measured on healthy records by
  /// tests/bearing/null_calibration.cpp (docs/bearing.md "Calibration").
  std::array<NullFit, 4> null = default_nulls();
  bool collect_surrogates = false;  ///< keep each family's surrogate scores (calibration)
  bool keep_spectra = false;        ///< keep each analysis band's normalised envelope spectrum (plots)
  static std::array<NullFit, 4> default_nulls();
  bool valid() const;
};

/// One searched line (find_line, for display and the model checks).
struct LineResult {
  double predicted_hz = 0.0;       ///< kinematic prediction, Hz
  std::optional<double> found_hz;  ///< frequency of the peak if it stands out, Hz
  double peak_hz = 0.0;            ///< largest bin in the window whether it stands out or not, Hz
  double ratio = 0.0;              ///< peak / local median floor, dimensionless
  double threshold = 0.0;          ///< k = sqrt(log2(n_window / p_fa)), dimensionless
  bool stands_out() const { return found_hz.has_value(); }
};

/// An analysis band of step 2.
struct AnalysisBand {
  std::string name;  ///< "whitened_full", "whitened_sk", "whitened_ees", "raw_sk", "discrete_removed_sk"
  Band band;         ///< edges, Hz, and spectral kurtosis of the signal it was chosen on (0 for whitened_ees)
  size_t sub_bands = 0;  ///< whitened_ees: disjoint bands of equal width combined (0: one band)
};

/// One family's evidence and decision.
struct FamilyResult {
  std::string name;                ///< "bpfo", "bpfi", "ball", "ftf"
  double predicted_hz = 0.0;       ///< base at the refined speed, Hz (ball: BSF)
  std::optional<double> found_hz;  ///< fitted fundamental if present (ball: BSF = 2 BSF line / 2), Hz
  size_t band_index = 0;           ///< the band where P_null is smallest (index into bands)
  double score = 0.0;              ///< -log10 Fisher p of the lines in that band (uncorrected)
  double threshold_score = 0.0;    ///< score at which log10 P_null reaches the threshold
  double log10_p = 0.0;            ///< log10 P_null(score) in that band
  std::vector<double> log10_p_per_band;  ///< the same in every band
  TemplateScore lines;             ///< per line at the best slip, in that band
  bool detected = false;
  double unique_score = 0.0;       ///< score on the lines no other detected family also found
  double unique_log10_p = 0.0;     ///< log10 P_null of unique_score (ranks detected families)
  std::vector<double> surrogates;  ///< surrogate scores of every band (collect_surrogates only)
  std::string reason;              ///< why it is named, or why it is not
};

/// The raw-signal cage scan of BearingCheckOptions::cage_modulation_as_ball (b).
struct RawCageScan {
  bool run = false;                 ///< made (no family detected in the whitened bands, or calibration)
  size_t bands = 0;                 ///< bands scanned
  Band band;                        ///< band of the smallest P_null
  double score = 0.0;               ///< cage template's score there (-log10 Fisher p)
  double log10_p = 0.0;             ///< log10 P_null of that score under the record's own null
  double threshold_log10_p = 0.0;   ///< log10(record_false_alarm / bands)
  double threshold_score = 0.0;     ///< score at which log10 P_null reaches the threshold
  bool detected = false;            ///< P_null below the threshold and the FTF line present on its own
  TemplateScore lines;              ///< per line, in that band
  std::vector<double> surrogates;   ///< surrogate scores of every scanned band: the scan's null
  NullFit null;                     ///< fitted to surrogates (the record's own null)
};

/// Everything bearing-check computed.
struct BearingCheckResult {
  model::bearing::DefectFrequencies predicted;  ///< kinematic frequencies at the nominal speed
  model::bearing::DefectFrequencies refined;    ///< at the refined speed
  SpeedRefinement speed;                        ///< step 5
  std::string speed_source;                     ///< "spectrum", "envelope spectrum" or "nominal"
  std::string whitening;                        ///< step 1, what was done
  std::vector<AnalysisBand> bands;              ///< steps 2-3
  std::array<FamilyResult, 4> families;         ///< bpfo, bpfi, ball, ftf
  double threshold_log10_p = 0.0;               ///< log10(record_false_alarm / (bands x families))
  double cage_teeth_ratio = 0.0;                ///< strongest cage tooth next to BPFO over its floor (0: not checked)
  RawCageScan raw_cage;                         ///< step 6's raw cage scan (cage_modulation_as_ball)
  /// Each analysis band's normalised envelope spectrum up to the highest line scored, as the
  /// family scores saw it (keep_spectra only; else empty). Index as bands.
  std::vector<NormalisedSpectrum> band_spectra;
  size_t verdict_band = 0;                      ///< band of the named family (or the first)
  std::string verdict;                          ///< outer_race, inner_race, ball, healthy, unclear
  std::string reason;                           ///< one sentence saying why
  const FamilyResult& family(const std::string& name) const;
};

/// Run the check. Throws std::invalid_argument on bad input (fs or speed not finite or <= 0,
/// defect lines beyond the usable band, short record, invalid geometry or options).
/// @param x               vibration record (acceleration, any unit)
/// @param fs_hz           sample rate, Hz
/// @param shaft_speed_hz  nominal shaft speed, Hz
BearingCheckResult check_bearing(const std::vector<double>& x, double fs_hz, double shaft_speed_hz,
                                 const model::bearing::BearingGeometry& g, const BearingCheckOptions& o = {});

/// Search one line in an envelope spectrum: the largest bin within +-rel_tolerance (>= 2 bins)
/// over the median of the floor window; stands out if the ratio exceeds the Rayleigh threshold.
LineResult find_line(const EnvelopeSpectrum& s, double predicted_hz, double rel_tolerance,
                     const BearingCheckOptions& o);

}  // namespace amb::host::bearing
