#pragma once
// Model-based identification of journal-bearing wear from one steady speed (seed 002
// section 2.5, eq. 24-25): the model's +1x/-1x full-spectrum components at the journal
// probes are fitted to the measured ones by varying the wear parameters within bounds:
// a design of experiments (full grid over the bounds, bounds included; the depth on a log
// scale, as the targets are relative) picks the starting
// points (the grid's local minima first, then other non-adjacent points), then NLopt's
// BOBYQA (bounded, derivative-free local optimiser) polishes each, restarted from its end
// point while that still gains. With the grid refinement (issue 33) a second such stage runs on a
// finer grid, the polishes' distinct end points (valleys) are polished on the refined grid, and
// the valley of lowest chi-square (the statistic the verdict uses, valley_ranking.hpp) wins.
// Cost: eq. 24 normalised by the measured spectrum,
//   cost = 1/2 sum_c |Z_c(model) - Z_c(measured)|^2 / (|Z+|^2 + |Z-|^2)_measured.
// Uncertainty (1 sigma): the measured components' noise propagated through the Jacobian of
// the residuals at the optimum, cov = sigma^2 (J^T J)^-1 (Gauss-Newton).
//
// The identification is given the event and the board only: never the wear it is after.
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/valley_ranking.hpp"
#include "model/journal/wear_geometry.hpp"

namespace amb::host::wearid {

struct WearIdOptions {
  model::journal::WearModel model = model::journal::WearModel::elliptical;  ///< two_parameter or elliptical
  std::array<double, 2> depth_um{5.0, 150.0};      ///< bounds on d0, um
  std::array<double, 2> position_deg{-45.0, 45.0}; ///< bounds on gamma, deg
  std::array<double, 2> span_deg{30.0, 150.0};     ///< bounds on beta (3p only), deg
  int doe_points = 9;                              ///< grid points per parameter (>= 2)
  int polished_starts = 8;                         ///< DOE grid local minima (then other non-adjacent points) polished by the local optimiser
  /// After the polishes, also polish from the winning start's face neighbours on the DOE grid
  /// (+-1 step per parameter, 2 n starts at most) that were not polished: the cost's valleys
  /// are narrow against the grid spacing.
  bool refine_neighbours = true;
  int max_restarts = 4;                            ///< BOBYQA restarts from a polish's end point (stop when the gain < 1e-3 of the cost)
  int max_evaluations = 400;                       ///< per local polish
  double xtol_rel = 1e-5;                          ///< on the scaled parameters
  int threads = 2;                                 ///< DOE evaluations in parallel
  double window_s = 2.0;                           ///< analysed time at the end of the record, s
  /// Also fit the +1x/-1x at the two AMB sensor planes (when the event has them). Default
  /// false, the seed's choice (journal probes only): on SIL data the AMB planes' response is
  /// dominated by the controller, whose frequency-domain model leaves a ~1 % misfit there,
  /// which biased the wear more than the extra residuals helped (docs/journal-bearing.md).
  bool use_amb_planes = false;
  /// Forward model with the full (nonlinear) Reynolds film instead of its linearisation:
  /// the steady orbit by harmonic balance (RigResponse::journal_probes_full_film, 1x and 2x,
  /// `film_samples` Reynolds solves per iteration). Default false: seed 002's linear film
  /// (eq. 22-23). At e = 0.7 the unbalance orbit is not small against the ~52 um minimum
  /// film: a full-film record's 1x differs from the linear model's by ~10 %
  /// (docs/journal-bearing.md, "The nonlinear film at e = 0.7"). Not with use_amb_planes.
  bool full_film = false;
  /// Also fit the +2x / -2x full-spectrum components at the journal probes (needs
  /// full_film): the film's second-order response, which depends on the wear profile over
  /// the arc the orbit sweeps. Residuals in the same units as the 1x ones (normalised by the
  /// record's 1x spectrum), each with the record's noise around 2x.
  bool second_harmonic = false;
  /// Relative model-error floor of the 1x residuals (0: none, the seed's equal weights):
  /// each 1x residual's standard deviation becomes sqrt(noise^2 + (floor |Z|)^2) instead of
  /// the noise alone, and the residuals are weighted accordingly (so that the residuals the
  /// forward model reproduces to noise level, e.g. the 2x, are not outweighed by a systematic
  /// 1x mismatch). The frequency-domain model's measured 1x mismatch to the SIL is 0.2-0.3 %
  /// of |Z+| on an unworn record (docs/journal-bearing.md, Rig checks).
  double model_error_1x = 0.0;
  int film_samples = 32;                           ///< full film: Reynolds solves per orbit (>= 8)
  double film_tolerance = 1e-6;                    ///< full film: harmonic-balance update, relative to |X1_linear|
  /// Full film: the AMBs' force law in the harmonic balance too (RigResponse::
  /// journal_probes_full_film): the AMBs carry the film's static load at a static gap and
  /// current, and their quadratic law makes a 2x of its own (~0.02 um at the journal probes at
  /// e = 0.7, docs/journal-bearing.md "The AMBs' own 2x"). false: linearised AMBs.
  bool amb_nonlinear = true;
  /// Full film: highest harmonic of the spin in the harmonic balance, 2..6. With 2 the
  /// orbit's 3x is neglected, and with it the film's 2x from the product of the 3x and the 1x
  /// (5 % of the 2x at e = 0.1, docs/journal-bearing.md "The 3x").
  int film_harmonics = 3;
  /// Converged film (issue 33): after the search on the board's grid, the film grid is refined
  /// at the winning wear until the estimated K/C error is below this (relative; 0.002 =
  /// 0.2 %; model/journal/film_grid_refinement.hpp) and the optimum is polished on that grid.
  /// 0 (the library's default, which the residual loop's journal path uses): the board's grid
  /// only, as before issue 33. `amb-host wear-id` defaults to 0.002 (--grid-tolerance).
  double grid_tolerance = 0.0;
  /// Global stage (issue 33): the distinct valleys the polishes end in (best first, at most
  /// this many) are each polished on the refined grid and compared by a chi-square level.
  int max_valleys = 4;
  /// Second global stage (issue 33, fifth round; with grid_tolerance > 0 and the linear film):
  /// a DOE of this many points per parameter over the whole box on an intermediate film grid
  /// (the board's cells doubled in both directions), BOBYQA polishes on that grid from its
  /// best local minima (up to `intermediate_starts`), and their distinct end points (up to
  /// max_valleys) join the board stage's valleys before the refined-grid polish. The board's
  /// grid is 1.3-3.7 % off in K/C at e = 0.7, enough to put its valleys in the wrong places.
  /// 0: off (the board stage only, as before the fifth round).
  int intermediate_doe_points = 5;
  int intermediate_starts = 4;  ///< polishes on the intermediate grid (>= 1)
  /// Confidence of the likelihood-ratio level that decides which valleys the records cannot
  /// reject and of the intervals (the chi-square quantile with as many degrees of freedom as
  /// wear parameters).
  double confidence = 0.95;
  /// When the result is not identified, trace the profile likelihood along d0 from each
  /// acceptable valley for the intervals (false: the Gauss-Newton intervals about each valley only).
  bool profile_likelihood = true;
  /// Progress lines ("design of experiments 120/729", "polish 3/8 starts done"); called from
  /// the worker threads one at a time (serialised here). Empty: silent.
  std::function<void(const std::string&)> progress;
  /// Empty when valid, else the reason.
  std::string check() const;
};

/// One valley of the cost (a distinct end point of the global stage's polishes).
struct WearValley {
  double d0_um = 0.0, gamma_deg = 0.0, beta_deg = 0.0;
  double cost = 0.0;      ///< the identification's cost at the valley's optimum
  double chi2 = 0.0;      ///< sum of (residual / its noise sigma)^2 there
  bool acceptable = false;  ///< chi2 within the level of the best valley's (the records cannot reject it)
  /// Acceptable valleys: each parameter's range where chi2 stays within the level, clipped to
  /// the bounds: the Gauss-Newton (quadratic) approximation about the valley, joined, when the
  /// result is not identified, with the profile likelihood traced from the valley along d0.
  std::array<double, 2> d0_interval_um{NAN, NAN}, gamma_interval_deg{NAN, NAN}, beta_interval_deg{NAN, NAN};
};

struct WearIdResult {
  std::string model;                 ///< "2p" or "3p"
  double d0_um = 0.0, gamma_deg = 0.0, beta_deg = 0.0;  ///< 2p: beta is the span the depth implies
  double d0_uncertainty_um = 0.0, gamma_uncertainty_deg = 0.0, beta_uncertainty_deg = 0.0;
  double cost = 0.0;
  int doe_evaluations = 0, evaluations = 0;
  int doe_local_minima = 0;          ///< starting points that were local minima of the DOE grid
  int refined_starts = 0;            ///< further polishes from the winning start's grid neighbours
  double wall_s = 0.0;
  std::string stop_reason;           ///< NLopt's result for the winning polish
  bool bound_active = false;         ///< a parameter ended on a bound (within 0.5 % of the range)
  JournalMeasurement measured;       ///< the (first) record
  int records = 1;                   ///< records fitted together
  FullSpectrum fitted;               ///< model spectrum at the optimum (journal probes)
  FullSpectrum fitted_2x;            ///< full film: model +-2x at the optimum (journal probes), m; zero otherwise
  bool used_full_film = false, used_second_harmonic = false;
  bool used_amb_planes = false;
  /// Film grid of the result (grid_tolerance > 0: the refined one) and its estimated relative
  /// K/C error (Richardson); the board's grid and how far its K/C are from the refined ones.
  int grid_theta = 0, grid_axial = 0;
  double grid_error_estimate = NAN;
  bool grid_converged = false;
  int coarse_grid_theta = 0, coarse_grid_axial = 0;
  double coarse_grid_error = NAN;
  /// Second global stage (WearIdOptions::intermediate_doe_points): its film grid (0: not run)
  /// and its evaluations (included in `evaluations`).
  int intermediate_grid_theta = 0, intermediate_grid_axial = 0, intermediate_evaluations = 0;
  int grid_iterations = 0;           ///< defect-correction rounds on the refined grid
  int fine_evaluations = 0;          ///< coefficient sets (or costs) evaluated on the refined grid
  double grid_wall_s = 0.0;          ///< time of the refinement and the polish on it, s
  /// Identifiable: one acceptable valley, and in it every parameter's 1-sigma within a quarter
  /// of its bound range and none on a bound. When not, `flat_direction` (unit vector in d0 um, gamma deg, beta deg) is the
  /// combination the records leave undetermined, with 1-sigma `flat_direction_sigma` along it.
  bool identified = false;
  std::array<double, 3> flat_direction{};
  double flat_direction_sigma = NAN;
  /// Global stage: the valleys found (best first), how many the records cannot reject, and
  /// the level: chi2 of a valley minus the best's <= chi2_scale * chi2_level, where chi2_level
  /// is the chi-square quantile (n parameters, WearIdOptions::confidence) and chi2_scale =
  /// max(1, chi2_min / chi2_dof) (the best fit's misfit beyond the noise, Birge ratio) from 8
  /// degrees of freedom, 1 below (one record: dof 1; two: dof 5).
  std::vector<WearValley> valleys;
  int acceptable_valleys = 0;
  double chi2_min = NAN, chi2_level = NAN, chi2_scale = 1.0;
  int chi2_dof = 0;  ///< residuals minus parameters
  /// Relative K/C error of the film in the chi-square (the refined grid's tolerance; 0 on the
  /// board's grid): propagated to each residual and added in quadrature to its noise sigma.
  double chi2_film_error = 0.0;
  int ranking_passes = 0;       ///< chi2 passes of the valley ranking (last round; rank_valleys_by_chi2)
  int profile_restarts = 0;     ///< profile points that beat the best valley: polished from, verdict redone
  int profile_points = 0;       ///< points of the profile likelihood (only when not identified)
  double profile_wall_s = 0.0;  ///< its time, s
  /// Union (hull) of the acceptable valleys' intervals: where the wear can be, at `confidence`.
  std::array<double, 2> d0_interval_um{NAN, NAN}, gamma_interval_deg{NAN, NAN}, beta_interval_deg{NAN, NAN};
  /// Parameters ("d0", "gamma", "beta") whose interval reaches beyond the identification
  /// targets around the estimate (d0 and beta 5 %, gamma 3 deg): the records leave them open.
  std::vector<std::string> ambiguous;
  /// Model comparison, unworn bore against the fitted wear (residual loop's criterion,
  /// host-tools/core/residual/engine/criterion.hpp, default settings): false = "no measurable wear".
  bool wear_measurable = false;
  double unworn_cost = NAN;          ///< cost of the unworn bore, same forward model
  double delta_bic = NAN;            ///< BIC(unworn) - BIC(wear), 1
  double effect_sigma = NAN;         ///< largest change of a residual between the two, noise sigmas
  std::string decision_reason;       ///< the criterion's reason in words
};

/// Quantile of the chi-square distribution with `dof` (1..3) degrees of freedom at probability p.
double chi_square_quantile(int dof, double p);

/// Run the identification on a measurement. Throws std::invalid_argument on bad options.
WearIdResult identify_wear(const board::BoardConfig& board, const JournalMeasurement& meas, const WearIdOptions& o);
/// The same with several records of one bearing fitted together (seed 002 measures each wear
/// at static eccentricities 0.1 and 0.7): each record's residuals are normalised by its own
/// spectrum, the cost is their sum. `fitted`/`measured` refer to the first record.
WearIdResult identify_wear(const board::BoardConfig& board, const std::vector<JournalMeasurement>& meas,
                           const WearIdOptions& o);

/// The identification's cost (what identify_wear minimises, with these options) at one wear:
/// e.g. at a known truth, to tell a search that stopped short from a model that prefers
/// another wear. 1e3 where the model cannot represent the wear.
double wear_cost(const board::BoardConfig& board, const std::vector<JournalMeasurement>& meas, const WearIdOptions& o,
                 const model::journal::WearParams& wear);

/// The film's relative K/C error `relative_error` propagated to the identification's residuals
/// at one wear (what identify_wear adds in quadrature to each residual's noise sigma in its
/// chi-square, with the refinement tolerance, issue 33 third round): each of the 8 entries of K
/// and C gets an independent error of standard deviation relative_error ||K||_F / 2 (||C||_F / 2).
/// One value per residual, in identify_wear's order (per record: +1x re, im, -1x re, im at the
/// journal probes, ...) and units (each record's measured spectrum norm), on the film grid of
/// `board` (no refinement here). Linear film only: zeros with o.full_film or relative_error 0.
std::vector<double> film_error_sigma(const board::BoardConfig& board, const std::vector<JournalMeasurement>& meas,
                                     const WearIdOptions& o, const model::journal::WearParams& wear, double relative_error);

/// Forward model for one wear (for sweeps, reports and tests): full spectrum at the journal
/// probes with the journal at `state` and the speed given.
FullSpectrum predict_spectrum(const board::BoardConfig& board, const model::journal::WearParams& wear,
                              const model::journal::JournalState& state, double speed_hz);
/// The same with the full (nonlinear) film by harmonic balance: +-1x and +-2x at the journal
/// probes with the journal's mean position at `mean` (see RigResponse::journal_probes_full_film).
FullFilmSpectrum predict_full_film(const board::BoardConfig& board, const model::journal::WearParams& wear,
                                   const model::journal::JournalState& mean, double speed_hz,
                                   const HarmonicBalanceOptions& options = {32, 60, 1e-6});

}  // namespace amb::host::wearid
