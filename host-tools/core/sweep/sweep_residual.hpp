#pragma once
// The residual loop on the board's own loop sweep (record kind "sweep" of the engine,
// host-tools/core/residual/engine): the misfit between the measured S and G (sweep_estimate)
// and the board's model (sweep_model) is explained by candidate elements of the catalogue
// that a closed-loop sweep can test -- amplifier_lag, pedestal_resonance, sensor_gain --
// each fitted within its physical bounds (NLopt, normalised bounded coordinates, several
// starts), added one at a time (forward selection, the largest information-criterion decrease
// first, everything refitted) after the board's force constant is updated (model updating, not an
// element), and kept or rejected by the engine's one criterion
// (engine::decide). It shares the TUM sweep path's data container and error figures
// (residual/frf_update.hpp: FrfFitData, frf_errors; the same weighted complex log misfit
// sum w |ln(H_meas / H_model)|^2) and its candidate reporting (CandidateScore, EffectAdded).
//
// Likelihood (stated): per compared line and function (S, G), ln H_meas - ln H_model is
// complex Gaussian with variance v = (sigma / |H|)^2 + floor^2: sigma from the period scatter
// (the estimate's band), floor the model's stated accuracy (SweepResidualOptions). The
// information criterion is BIC = 2 sum |d|^2 / v + p ln(n), n the real data points.
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/residual/engine/criterion.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/sweep/sweep_estimate.hpp"
#include "host-tools/core/sweep/sweep_model.hpp"
#include "model/effects/effect_set.hpp"

namespace amb::host::sweep {

struct SweepResidualOptions {
  residual::engine::Criterion criterion;  ///< the engine's one keep/reject criterion
  /// The linearised model's relative accuracy on a clean record, added in quadrature to each
  /// line's estimator variance (1 %: the exact discrete loop against the nonlinear simulated
  /// plant, tests/sil/loop_delay_test and the sweep SIL tests, agree to about 1 %).
  double model_error_floor = 0.01;
  double min_coherence = 0.9;             ///< lines whose S coherence is below this are not compared
  int max_effects = 2;                    ///< elements added at most
  int max_evaluations = 150;              ///< per bounded refinement
};

/// Error figures of one model against the measured lines (compared lines only).
struct SweepFit {
  double misfit = 0.0;           ///< sum |ln(H_meas / H_model)|^2 / v over S and G, 1
  double bic = 0.0;              ///< 2 misfit + p ln(n)
  int parameters = 0;
  int data_points = 0;           ///< real values compared (2 per line and function)
  double s_db_rms = 0.0;         ///< rms of 20 log10 |S_meas / S_model|, dB
  double g_db_rms = 0.0;         ///< rms of 20 log10 |G_meas / G_model|, dB
  std::vector<double> model_peak;       ///< per axis: the model's largest |S| over the swept band
  std::vector<double> model_peak_hz;    ///< its frequency, Hz
  std::vector<std::string> model_zone;  ///< its ISO 14839-3 zone
  std::vector<double> peak_ratio;       ///< per axis: measured peak / model peak
  std::vector<std::vector<ModelResponse>> lines;  ///< [axis][line]
};

/// Model updating of the board's own uncertain parameter before any element (not an element).
struct SweepModelUpdate {
  bool done = false;
  double force_scale = 1.0;   ///< fitted actuator force constant / board's, 1
  double delta_bic = 0.0;     ///< BIC(board) - BIC(updated)
  bool at_bound = false;
  bool kept = false;          ///< delta_bic > the criterion's min_delta_ic and not on a bound
};

struct SweepResidualOutcome {
  SweepFit before, after;
  SweepFit updated;                                ///< the base model after model updating (= before when not kept)
  SweepModelUpdate update;
  std::vector<residual::CandidateScore> ranking;   ///< every candidate decided on or screened out, in order
  std::vector<residual::EffectAdded> effects_added;
  model::effects::EffectSet found;                 ///< the elements kept, with their fitted values
  std::string verdict;                             ///< "none" or the kept names joined with "+"
  std::vector<std::string> notes;
};

/// The loop on one estimated record. `m` must be built on the record's axes and lines.
SweepResidualOutcome run_sweep_residual(const SweepEstimate& e, const SweepLoopModel& m, const SweepResidualOptions& o = {});

}  // namespace amb::host::sweep
