#pragma once
// Learned correction after the named elements (issue 18, seed 001's "data mapping" applied to
// the residual loop). It is NOT a physical explanation and never enters the named verdict:
// it runs on the loop's final model (a const input), after the loop has decided, and says how
// much of what no element explains a smooth, regularised map could absorb.
//
// The map, per channel group g (e.g. the two sensors of one bearing plane), on a grid of
// log-spaced frequencies f (relative-width bands), in the log domain:
//
//   r^(f) = sum_t T_t(log2 f) a_{g,t}  +  sum_b B_b(log2 f) c_{g,b} p(f)
//
//   r = ln(measured level) - ln(model level)            the unexplained part of the spectrum
//   T_t: hat functions over log2 f, knot_spacing_octaves apart (a transfer path: sensor or
//        acquisition chain, housing; a gain shaping smooth over a fraction of an octave)
//   B_b: gain_bands wide hats; p = the model's log level minus its local mean over
//        +-local_halfwidth_octaves (the model's own peaks: a gain on them says the model's
//        resonances are too sharp or too shallow)
// Nothing is per bin, so the map cannot memorise a spectrum bin by bin. Ridge regression,
// solved exactly (Eigen LDLT on the normal equations, columns scaled to unit mean square,
// rows weighted by the inverse of each point's nominal estimator variance `noise_var_ln`);
// the ridge penalty is chosen from a fixed list by generalised cross-validation on the
// training part only. Deterministic: no random start, no iteration, no seed needed.
//
// Honesty: the map is trained on one part of the data and scored on another that it never
// saw (steady record: first half of the steady window against the second half, and the
// reverse as a check; sweep: odd accelerometers against even ones). The figures are those of
// the held-out part; memorising the training part cannot lower them. The model (the loop's
// final model) was fitted on the whole record, which favours "before", not "after".
//
// Operating point: the map is learned per record; a steady record or a sweep has one
// operating point (one speed), so the map cannot be conditioned on it (an input that does not
// vary in training carries no information; host-tools/core/hybrid gives it scale 0 for the
// same reason). Across records at several speeds it could be; not done.
#include <string>
#include <vector>

#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/residual/steady_fit.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"

namespace amb::host::residual {

/// One channel's spectrum on a frequency grid, in the log domain, with the model's prediction.
struct CorrectionSpectrum {
  int group = 0;                    ///< channel group sharing one map, 0 .. groups-1
  std::string channel;              ///< channel label (e.g. "A1", "accel 3")
  std::vector<double> f_hz;         ///< grid frequencies, Hz, ascending, > 0
  std::vector<double> measured_ln;  ///< ln of the measured level (PSD: unit^2/Hz; FRF: |H|), per grid point
  std::vector<double> model_ln;     ///< ln of the model's level as the estimator would see it (its expected log bias included), per grid point
  std::vector<double> noise_var_ln; ///< variance of measured_ln from the estimate's own noise, ln^2 (0: unknown)
};

/// A set of spectra (one part of a record) and how its log levels convert to dB.
struct CorrectionPart {
  std::string name;                 ///< e.g. "first half of the steady window (1.00 s)"
  std::vector<CorrectionSpectrum> spectra;
  double db_per_ln = 10.0 / 2.302585092994046;  ///< dB per natural-log unit: PSD 10/ln 10, FRF magnitude 20/ln 10
};

struct LearnedCorrectionOptions {
  double knot_spacing_octaves = 0.5;    ///< spacing of the transfer-path hats over log2 f, octaves (> 0)
  int gain_bands = 4;                   ///< wide hats for the gain on the model's prominence (>= 1)
  double local_halfwidth_octaves = 0.375; ///< local mean of the model's log level over +- this, octaves (> 0)
  /// Ridge penalties tried (relative to the mean square of a design column x training points);
  /// the one with the lowest generalised cross-validation score on the training part is used.
  std::vector<double> lambdas = {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0};
  /// GCV score n RSS / (n - gamma edf)^2: gamma > 1 charges each effective parameter more than
  /// plain GCV, which is known to overfit at these sample sizes (Kim & Gu 2004 recommend 1.4;
  /// mgcv's `gamma`), 1
  double gcv_gamma = 1.4;
  /// Steady record: shortest half of the steady window, s (at least 3 Welch segment lengths,
  /// i.e. 5 segments with 50 % overlap; the default 0.75 s with 0.25 s segments)
  double min_half_s = 0.75;
  bool valid(std::string* why = nullptr) const;
};

/// Error of a part against the model, with and without the map.
struct CorrectionScore {
  double before_db = 0.0;           ///< rms over channels and grid points of measured - model, dB (as ErrorFigures::spectral)
  double after_db = 0.0;            ///< the same with the learned correction added to the model, dB
  double noise_floor_db = 0.0;      ///< rms the estimate's own noise alone gives (a perfect model scores about this), dB
  double absorbed_fraction = 0.0;   ///< 1 - after^2 / before^2 (of the mean square error; < 0: the map made it worse), 1
  /// (before^2 - after^2) / (before^2 - floor^2): share of the error beyond the estimate's
  /// noise that the map absorbs; NaN when before is within 10 % (in mean square) of the floor.
  double absorbed_fraction_of_excess = 0.0;
  int points = 0;                   ///< channel-grid points scored
};

struct GroupScore {
  std::string name;                 ///< e.g. "sensors A"
  double lambda = 0.0;              ///< ridge penalty chosen (GCV, training part)
  double effective_parameters = 0.0;///< trace of the ridge hat matrix, 1
  int weights = 0;                  ///< unknowns of the group's map
  CorrectionScore held_out;         ///< on the scored part
};

struct LearnedCorrectionSummary {
  bool done = false;
  std::string skipped_why;          ///< why not, when not done (a stated skip, not an error)
  std::string domain;               ///< "log PSD per channel, 1/8-octave bands" or "log |H| per accelerometer"
  std::string trained_on, scored_on;
  CorrectionScore held_out;         ///< the figures to report: scored part, never seen in training
  CorrectionScore training;         ///< on the training part (for comparison only: optimistic by construction)
  bool has_reverse = false;
  std::string reverse_trained_on, reverse_scored_on;
  CorrectionScore reverse_held_out; ///< the roles of the parts swapped (check of the first figure)
  std::vector<GroupScore> groups;   ///< per channel group, primary fold
  int weights = 0;                  ///< unknowns of the map, all groups
  double effective_parameters = 0.0;///< sum of the groups' effective parameters, 1
  int training_points = 0;          ///< channel-grid points the map was trained on
  double knot_spacing_octaves = 0.0;
  int gain_bands = 0;
  std::string noise_floor_source;   ///< how noise_floor_db was obtained (split-half difference, or the estimates' nominal variance)
  std::string note;                 ///< "learned correction: not a physical explanation ..."
};

/// Train on `train`, score on `test` (same channels and groups, same grid per channel).
/// `group_names[g]` names group g. Throws std::invalid_argument on inconsistent parts.
LearnedCorrectionSummary learned_correction(const CorrectionPart& train, const CorrectionPart& test,
                                            const std::vector<std::string>& group_names,
                                            const LearnedCorrectionOptions& o = {});

/// Spectra of one half of a steady record's steady window (`half` 0: first, 1: second), on
/// the bands of `d` (same Welch segment, same band edges, same speed-line exclusions), with
/// the model's PSD of `model` (the loop's final evaluation). Welch as extract_steady() does it:
/// mean and speed orders removed by least squares on that half first. Groups: 0 sensors A,
/// 1 sensors B, 2 currents AMB A, 3 currents AMB B. Throws std::runtime_error when the half
/// is shorter than 3 Welch segment lengths or its bands differ from d's.
CorrectionPart steady_half_part(const SteadyData& d, const SteadyEvaluation& model, int half, const SteadyOptions& so = {});

/// The steady record's learned correction: first half -> second half (and the reverse).
/// A steady window shorter than 2 x min_half_s gives a stated skip (done = false), not an error.
LearnedCorrectionSummary learned_correction_steady(const SteadyData& d, const SteadyEvaluation& model,
                                                   const LearnedCorrectionOptions& o = {}, const SteadyOptions& so = {});

/// The sweep's learned correction on log |H| over the compared bins: odd accelerometers
/// (1, 3, ...) -> even ones (and the reverse). One group (all accelerometers share one map:
/// a per-accelerometer path cannot be scored on another accelerometer). Fewer than 2
/// channels with compared bins: a stated skip.
LearnedCorrectionSummary learned_correction_sweep(const SweepOutcome& s, const LearnedCorrectionOptions& o = {});

}  // namespace amb::host::residual
