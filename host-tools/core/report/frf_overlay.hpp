#pragma once
// Measured vs modelled FRF magnitudes overlaid, one panel per channel, as one SVG document
// (panels from svg_plot's line plot nested in a grid). Bins that were not compared (low
// coherence, outside the band) are drawn as a thin grey measured line only.
#include <complex>
#include <string>
#include <vector>

namespace amb::host::report {

struct FrfOverlay {
  std::string title;
  std::vector<double> f_hz;                                    ///< bins, Hz
  std::vector<std::string> channel_names;
  std::vector<std::vector<std::complex<double>>> measured;     ///< [channel][bin]
  std::vector<std::vector<bool>> compared;                     ///< [channel][bin]
  std::vector<std::vector<std::complex<double>>> before, after;///< models [channel][bin]
  std::string unit = "(m/s^2)/A";
  std::string before_label = "model before", after_label = "model after";
};

/// The SVG document (standalone, with XML header).
std::string render_frf_overlay_svg(const FrfOverlay& o);

}  // namespace amb::host::report
