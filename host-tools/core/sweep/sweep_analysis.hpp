#pragma once
// The host's analysis of one loop-sensitivity sweep (issue 35), the one call `amb-host sweep`
// and `amb-host residual SWEEP_EVENT` make after decoding the board's event:
//   estimate (sweep_estimate.hpp) -> the board's model beside it (sweep_model.hpp) -> error
//   figures -> the residual loop (sweep_residual.hpp) -> JSON and the HTML page
//   (host-tools/core/report/sweep_page.hpp).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "host-tools/core/sweep/sweep_estimate.hpp"
#include "host-tools/core/sweep/sweep_record.hpp"
#include "host-tools/core/sweep/sweep_residual.hpp"

namespace amb::host::sweep {

struct SweepAnalysisOptions {
  EstimateOptions estimate;
  SweepResidualOptions residual;
  bool run_residual = true;   ///< false: estimate and model overlay only (fast)
  /// Fewest recorded periods the residual loop runs on: its criterion weighs the misfit by each
  /// line's period-to-period variance, poorly known from few periods (a clean 2-period sweep of
  /// the target rig named a pedestal); the loop's false-alarm rate was measured on 6-period
  /// sweeps (docs/sweep.md). Fewer: the loop is not run and a note says why (the zone and the
  /// model overlay are still given).
  uint32_t min_residual_periods = 4;
};

/// Per axis: the zone table row (ISO 14839-3 on the peak of |S|).
struct ZoneRow {
  int axis = 0;
  std::string axis_name;        ///< "A1", "A2", "B1", "B2"
  PeakEstimate measured;        ///< peak, band, frequency, zone, statement
  double model_peak = 0.0;      ///< the board's model: largest |S| over the swept band
  double model_peak_hz = 0.0;
  std::string model_zone;
  double peak_error_pct = 0.0;  ///< 100 (measured / model - 1)
};

struct SweepAnalysis {
  std::string board_name, rig_name;
  double rate_hz = 0.0, speed_hz = 0.0;
  ExcitationPlan plan;
  bool aborted = false;
  std::string abort_reason;
  SweepEstimate measured;
  std::vector<std::vector<ModelResponse>> model;  ///< the board's prediction [axis][line]
  std::vector<ZoneRow> zones;
  double s_db_rms = 0.0, g_db_rms = 0.0;          ///< measured vs the board's model over the compared lines
  bool residual_done = false;
  SweepResidualOutcome residual;
  std::vector<std::string> notes;
};

/// Everything for one record on its board. Throws std::invalid_argument naming what is wrong
/// with the record (no axes, a line off the period's bins, wrong lengths, an axis the board
/// lacks) and std::runtime_error when the model cannot be built.
SweepAnalysis analyse_sweep(const SweepRecord& r, const board::BoardConfig& b, const SweepAnalysisOptions& o = {});

/// The figures as JSON (zones per axis with peak, band, frequency; errors before/after;
/// candidates and verdict; lines with measured and modelled S, T, G).
nlohmann::json sweep_analysis_json(const SweepAnalysis& a);

/// "A1", "A2", "B1", "B2".
const char* axis_name(int axis);

}  // namespace amb::host::sweep
