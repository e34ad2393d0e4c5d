#pragma once
// The fleet page: one self-contained HTML file (inline CSS and SVG, no scripts): the
// bearings nearest their budget (table "nearest"), life-used curves per bearing (plot
// "trend", drawn with host-tools/core/report/svg_plot), and the machines (table "machines").
#include <string>
#include <vector>

#include "host-tools/core/fleet/fleet_store.hpp"

namespace amb::host::fleet {

struct FleetPageData {
  std::string store;                       ///< what the page is of (store URL or path; no password)
  std::vector<MachineSummary> machines;
  std::vector<BearingStatus> nearest;      ///< nearest_budget()
  std::vector<TrendPoint> trend;           ///< trend()
  int max_curves = 24;                     ///< curves drawn in the trend plot (nearest first)
};

std::string render_fleet_page(const FleetPageData& d);

}  // namespace amb::host::fleet
