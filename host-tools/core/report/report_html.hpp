#pragma once
// The event report as one self-contained HTML file: inline CSS and inline SVG plots, no
// scripts, no external resources. Sections in order: event facts, replay verdict, orbits,
// contact angle and rubbing states, speed, contact forces, load over the circumference,
// fit convergence, residual spectra, wear record, notes. A section without data shows a
// "not available: <why>" box (element id "<section>-na").
#include <string>
#include <vector>

#include "host-tools/core/report/report_data.hpp"

namespace amb::host::report {

/// The whole page.
std::string render_event_report(const ReportData& d);

/// Write the page to `path` (parent directories are created). Returns the absolute path
/// written. Throws std::runtime_error naming the path if it cannot be written.
std::string write_event_report(const ReportData& d, const std::string& path);

/// Ids of the <svg> elements render_event_report() emits for `d` (for checks and tests).
std::vector<std::string> plot_ids(const ReportData& d);
/// Ids of the "not available" boxes it emits for `d`.
std::vector<std::string> unavailable_ids(const ReportData& d);

}  // namespace amb::host::report
