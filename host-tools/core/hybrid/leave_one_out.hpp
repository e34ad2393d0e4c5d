#pragma once
// Leave-one-operating-point-out evaluation of the hybrid model and its four baselines
// (issue 34): for every operating point of the records, train on the records of the other
// points, predict every record of the held-out point and score the five models (Pearson and
// MSE, log spectrum and envelope spectrum) and the hybrid's band (coverage).
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "host-tools/core/hybrid/hybrid_model.hpp"

namespace amb::host::hybrid {

/// One held-out record.
struct LooRow {
  OperatingPoint held_out;
  BearingState state = BearingState::healthy;
  std::string record;                 ///< path of the measured record
  std::vector<ModelScore> models;     ///< score_table() order
  std::string hybrid_kind;            ///< Prediction::hybrid_kind
  std::string chosen_log, chosen_env; ///< correction chosen by the inner cross-validation ("" without)
  /// Inner cross-validation (training points only): mean Pearson of the chosen correction and of
  /// the uncorrected single-source transport.
  double cv_log = 0, cv_log_baseline = 0, cv_env = 0, cv_env_baseline = 0;
  /// Fraction of grid bins where the measured spectrum lies inside the hybrid's band.
  double band_coverage_log = 0, band_coverage_env = 0;
  /// Mean band width: log10 units (log spectrum); relative to the mean measured amplitude (envelope).
  double band_width_log = 0, band_width_env_rel = 0;
  const ModelScore& model(const std::string& name) const;
};

struct LooResult {
  std::vector<LooRow> rows;
  std::vector<double> train_wall_s;  ///< one per fold
};

/// Run it. `records` must be loaded and span at least two operating points; `progress` (may be
/// empty) receives one line per step. Throws std::invalid_argument on bad input.
LooResult leave_one_point_out(const std::vector<Record>& records, const TrainOptions& o,
                              const std::function<void(const std::string&)>& progress = {});

/// JSON of a result (rows with every model's Pearson and MSE).
nlohmann::json loo_json(const LooResult& r);

}  // namespace amb::host::hybrid
