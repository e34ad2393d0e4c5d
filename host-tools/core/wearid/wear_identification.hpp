#pragma once
// Model-based identification of journal-bearing wear from one steady speed (seed 002
// section 2.5, eq. 24-25): the model's +1x/-1x full-spectrum components at the journal
// probes are fitted to the measured ones by varying the wear parameters within bounds:
// a design of experiments (full grid over the bounds, bounds included; the depth on a log
// scale, as the targets are relative) picks the starting
// points (the grid's local minima first, then other non-adjacent points), then NLopt's
// BOBYQA (bounded, derivative-free local optimiser) polishes each, restarted from its end
// point while that still gains; the best polish wins. Cost: eq. 24 normalised by the measured spectrum,
//   cost = 1/2 sum_c |Z_c(model) - Z_c(measured)|^2 / (|Z+|^2 + |Z-|^2)_measured.
// Uncertainty (1 sigma): the measured components' noise propagated through the Jacobian of
// the residuals at the optimum, cov = sigma^2 (J^T J)^-1 (Gauss-Newton).
//
// The identification is given the event and the board only: never the wear it is after.
#include <array>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "model/journal/wear_geometry.hpp"

namespace amb::host::wearid {

struct WearIdOptions {
  model::journal::WearModel model = model::journal::WearModel::elliptical;  ///< two_parameter or elliptical
  std::array<double, 2> depth_um{5.0, 150.0};      ///< bounds on d0, um
  std::array<double, 2> position_deg{-45.0, 45.0}; ///< bounds on gamma, deg
  std::array<double, 2> span_deg{30.0, 150.0};     ///< bounds on beta (3p only), deg
  int doe_points = 9;                              ///< grid points per parameter (>= 2)
  int polished_starts = 8;                         ///< DOE grid local minima (then other non-adjacent points) polished by the local optimiser
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
  /// Empty when valid, else the reason.
  std::string check() const;
};

struct WearIdResult {
  std::string model;                 ///< "2p" or "3p"
  double d0_um = 0.0, gamma_deg = 0.0, beta_deg = 0.0;  ///< 2p: beta is the span the depth implies
  double d0_uncertainty_um = 0.0, gamma_uncertainty_deg = 0.0, beta_uncertainty_deg = 0.0;
  double cost = 0.0;
  int doe_evaluations = 0, evaluations = 0;
  int doe_local_minima = 0;          ///< starting points that were local minima of the DOE grid
  double wall_s = 0.0;
  std::string stop_reason;           ///< NLopt's result for the winning polish
  bool bound_active = false;         ///< a parameter ended on a bound (within 0.5 % of the range)
  JournalMeasurement measured;       ///< the (first) record
  int records = 1;                   ///< records fitted together
  FullSpectrum fitted;               ///< model spectrum at the optimum (journal probes)
  bool used_amb_planes = false;
};

/// Run the identification on a measurement. Throws std::invalid_argument on bad options.
WearIdResult identify_wear(const board::BoardConfig& board, const JournalMeasurement& meas, const WearIdOptions& o);
/// The same with several records of one bearing fitted together (seed 002 measures each wear
/// at static eccentricities 0.1 and 0.7): each record's residuals are normalised by its own
/// spectrum, the cost is their sum. `fitted`/`measured` refer to the first record.
WearIdResult identify_wear(const board::BoardConfig& board, const std::vector<JournalMeasurement>& meas,
                           const WearIdOptions& o);

/// Forward model for one wear (for sweeps, reports and tests): full spectrum at the journal
/// probes with the journal at `state` and the speed given.
FullSpectrum predict_spectrum(const board::BoardConfig& board, const model::journal::WearParams& wear,
                              const model::journal::JournalState& state, double speed_hz);

}  // namespace amb::host::wearid
