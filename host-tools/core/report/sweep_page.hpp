#pragma once
// The loop-sensitivity sweep report (issue 35) as one self-contained HTML page, built like the
// event report (report_html.hpp: inline CSS and SVG from svg_plot, no scripts): the sweep's
// facts, the ISO 14839-3 zone table per axis (zone, measured peak of |S| with its band and
// frequency, the board model's peak), the error against the model before and after the
// residual loop with its candidates, and per axis the Bode plots of S, T and G (magnitude in
// dB and phase; measured with its confidence band, the board's model, the model with the
// elements found) and the coherence.
#include <string>
#include <vector>

#include "host-tools/core/sweep/sweep_analysis.hpp"

namespace amb::host::report {

/// The whole page.
std::string render_sweep_page(const sweep::SweepAnalysis& a);

/// Write it to `path` (parent directories created); returns the absolute path. Throws
/// std::runtime_error naming the path when it cannot be written.
std::string write_sweep_page(const sweep::SweepAnalysis& a, const std::string& path);

/// Ids of the <svg> plots render_sweep_page() emits (for checks and tests).
std::vector<std::string> sweep_plot_ids(const sweep::SweepAnalysis& a);

}  // namespace amb::host::report
