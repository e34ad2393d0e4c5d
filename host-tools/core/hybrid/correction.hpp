#pragma once
// The learned part of the hybrid model with several training operating points (issue 34): a
// correction of the transported measured spectrum (transport_base.hpp) from physics features.
//
//   y_k = b_k + d [ sum_b B_b(k) sum_j w_bj f_j(k) / s_j + sum_t T_t(k) a_t ]
//
// d = min(c, c_max) / c_max, c = |ln(target speed / source speed)|: the correction is first order
// in the speed change of the transport (zero for a source at the target speed) and is not
// extrapolated beyond the largest change seen in training (c_max).
// b: the base, the training spectra of the state moved to the queried speed and interpolated
// (the best no-learning baseline, so the correction starts from it: all weights 0 is the
// baseline itself). Features f_j at bin k (each optional, chosen by inner cross-validation):
//   0 base_lines   b_k minus its local mean (sharpen / blur the moved lines per band),
//   1 base_level   the local mean of b (broadband level gain per band),
//   2 fixed_lines  the same training spectra NOT moved, minus their local mean (lines that do
//                  not follow the shaft speed: supply frequency, structural resonances),
//   3 sim_lines    the 8-DOF simulation at the queried point minus its local mean (line
//                  amplitudes the physics moves with speed and state),
//   4 sim_level    the local mean of the simulation.
// s_j: the rms of feature j over the training rows (standardised inputs). B_b: `bands` wide
// hats over the bin index, T_t: narrow hats every `offset_spacing_bins` bins (a smooth offset:
// a transfer-path or load change). Ridge regression (one penalty `lambda` on every weight,
// towards the baseline), solved exactly with Eigen LDLT: deterministic, no iteration.
//
// Domain: log10 PSD for the log spectrum; envelope AMPLITUDE (the scored quantity) for the
// envelope spectrum (callers pass amplitudes).
//
// Why a closed-form ridge and not a network (docs/hybrid.md, "Learner"): the training set of one
// leave-one-operating-point-out fold is two operating points x three states, i.e. six
// independent cases; a correction with tens of weights is what six cases determine, and the
// exact solve makes training bit-for-bit reproducible and the inner cross-validation over
// dozens of candidates cost milliseconds.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace amb::host::hybrid {

inline constexpr int k_correction_features = 5;
/// Feature names, in feature order (model file, docs).
const char* correction_feature_name(int j);

struct CorrectionOptions {
  unsigned features = 0;          ///< bit j set: feature j used (0: the baseline itself, no weight)
  int bands = 4;                  ///< wide hats for the feature gains (>= 1)
  int offset_spacing_bins = 0;    ///< spacing of the smooth-offset hats, bins (0: no offset)
  int local_halfwidth_bins = 3;   ///< local mean over +-this many bins (>= 1)
  double lambda = 0.1;            ///< ridge penalty on every weight (standardised features), > 0
  bool valid(std::string* why = nullptr) const;
  std::string describe() const;   ///< e.g. "base_lines+sim_lines, 4 bands, offset 32, lambda 0.1"
};

/// One case of the correction: its inputs on the grid and its measured target(s).
struct CorrectionCase {
  int group = 0;                     ///< operating point index (the cross-validation fold)
  /// |ln(target speed / source speed)| of the transport (> 0 in training). The correction is
  /// first order in it: the whole correction term is multiplied by min(change, c_max) / c_max,
  /// c_max the largest change in training (a source at the target speed needs no correction;
  /// the correction is not extrapolated beyond the speed changes it was trained on).
  double speed_change = 0.0;
  std::vector<double> base, fixed, sim;   ///< inputs (see the header comment), grid bins each
  std::vector<std::vector<double>> segments;  ///< measured spectra of the case's segments (targets)
};

class Correction {
 public:
  /// Fit on `cases` (every segment a row; `weights`, if given, one per case x segment in
  /// order: a bootstrap multiplicity). Throws std::invalid_argument on inconsistent input.
  void train(const std::vector<CorrectionCase>& cases, const CorrectionOptions& o,
             const std::vector<double>* weights = nullptr);
  /// Corrected spectrum of one case (only base, fixed and sim are read).
  std::vector<double> predict(const CorrectionCase& in) const;
  bool trained() const { return bins_ > 0; }
  size_t bins() const { return bins_; }
  const CorrectionOptions& options() const { return o_; }
  nlohmann::json to_json() const;
  static Correction from_json(const nlohmann::json& j);

 private:
  void features(const CorrectionCase& c, std::vector<std::vector<double>>& f) const;
  size_t offset_hats() const;
  size_t unknowns() const;
  CorrectionOptions o_{};
  size_t bins_ = 0;
  std::vector<double> scale_;  // per feature (0: unused)
  std::vector<double> w_;      // [bands x used features | offset hats]
  double change_max_ = 0.0;    // largest speed change in training
};

/// Inner cross-validation: every candidate is fitted with one operating point (group) left
/// out and scored on it (mean Pearson of the held-out cases' corrected spectra against their
/// mean measured spectra); the baseline (no feature) is a candidate too. Needs >= 2 groups.
struct CvRow {
  CorrectionOptions options;
  double mean_pearson = 0.0;
};
struct CvResult {
  CorrectionOptions chosen;
  double chosen_pearson = 0.0, baseline_pearson = 0.0;
  std::vector<CvRow> rows;  ///< every candidate, in the order tried (not in the model file)
  size_t candidates = 0;    ///< how many were tried
};
CvResult select_correction(const std::vector<CorrectionCase>& cases, const std::vector<CorrectionOptions>& candidates);

/// The candidate grid of the hybrid (feature subsets x bands x offset x lambda; docs/hybrid.md).
/// `with_sim` false: no subset with the 8-DOF simulation's features (an ablation).
std::vector<CorrectionOptions> correction_candidates(int local_halfwidth_bins, int offset_spacing_bins, bool with_sim = true);

/// Central probability of the band's predictive part (inner cross-validation residual
/// quantiles), and the number of frequency bands those quantiles are taken over.
inline constexpr double k_band_coverage = 0.8;
inline constexpr int k_residual_bands = 8;

/// A trained correction with its ensemble (the band).
///
/// Band = [min over the ensemble + q_lo, max over the ensemble + q_hi]: the ensemble is the
/// corrections fitted with each training operating point left out and on bootstrap resamples of
/// the segments within each case (model uncertainty); q_lo / q_hi are the 10 % / 90 % quantiles
/// of the inner cross-validation's held-out residuals (measured minus predicted) per frequency
/// band (what a correction does not predict at an unseen operating point). Nominal coverage
/// k_band_coverage; the coverage reached on held-out points is measured (docs/hybrid.md).
struct CorrectionEnsemble {
  Correction main;                  ///< fitted on every training case
  std::vector<Correction> members;  ///< leave-one-point-out fits, then bootstrap fits
  std::vector<double> resid_lo, resid_hi;  ///< residual quantiles per band (k_residual_bands)
  /// Residuals relative to the mean |prediction| of their case (envelope amplitudes, whose
  /// scale differs by state) instead of absolute (log10 PSD). Set before train().
  bool relative_residuals = false;
  CvResult cv;
  /// Train: select by inner CV, fit `main`, the leave-one-point-out members and `members_bootstrap`
  /// bootstrap fits (std::mt19937_64 seeded with `seed`; reproducible bit for bit).
  void train(const std::vector<CorrectionCase>& cases, const std::vector<CorrectionOptions>& candidates,
             int members_bootstrap, uint64_t seed);
  /// Point prediction and the band of the weighted mix of the corrected inputs `in` (one per
  /// transport source, `weights` summing to 1): each source is corrected, then the corrected
  /// spectra are interpolated.
  void predict(const std::vector<CorrectionCase>& in, const std::vector<double>& weights, std::vector<double>& y,
               std::vector<double>& lo, std::vector<double>& hi) const;
  bool trained() const { return main.trained(); }
  nlohmann::json to_json() const;
  static CorrectionEnsemble from_json(const nlohmann::json& j);
};

}  // namespace amb::host::hybrid
