#pragma once
// The hybrid model's prediction as one self-contained HTML page (inline CSS and SVG, no
// scripts): the facts of the query, the five models' Pearson and MSE against a measured
// record (table id "hybrid-scores"), and two plots, the log spectrum ("hybrid-log-spectrum")
// and the envelope spectrum ("hybrid-envelope"), each with the measured spectrum, the hybrid,
// its band, and the baselines.
#include <string>
#include <vector>

#include "host-tools/core/hybrid/hybrid_model.hpp"

namespace amb::host::hybrid {

struct HybridPageData {
  BearingState state = BearingState::healthy;
  OperatingPoint op;
  std::string model_path;            ///< model file (shown as given)
  std::vector<std::string> trained_at;  ///< "state@rpm/load" of every training record
  Prediction prediction;
  std::string measured_path;         ///< empty: no measured record (no table, no measured curve)
  Spectra measured;                  ///< measured spectra on the model's grids (if measured_path)
  std::vector<ModelScore> scores;    ///< score_table() (if measured_path)
};

/// The whole page.
std::string render_hybrid_page(const HybridPageData& d);

/// Write the page to `path` whole or not at all (a temporary file renamed into place). Throws
/// std::runtime_error naming the path if it cannot be written.
void write_hybrid_page(const HybridPageData& d, const std::string& path);

/// Ids of the <svg> elements the page holds.
std::vector<std::string> hybrid_page_plot_ids();

}  // namespace amb::host::hybrid
