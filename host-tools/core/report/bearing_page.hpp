#pragma once
// bearing-check's result as one self-contained HTML page (amb-host bearing-check --plot): the
// record, the speed, the verdict and its reason, every family's score, threshold and decision,
// and for each analysis band its normalised envelope spectrum with every family's template lines
// marked where the score found them (so a person sees the lines the verdict rests on, and the
// ones it rejected).
#include <string>
#include <vector>

#include "host-tools/core/bearing/bearing_check.hpp"

namespace amb::host::report {

/// What the page says about the record besides the result.
struct BearingPageInfo {
  std::string record;       ///< file name (no directories), for the title
  std::string variable;     ///< channel, e.g. "DE_time"
  std::string bearing;      ///< catalogue name
  double fs_hz = 0.0;       ///< sample rate, Hz
  double nominal_rpm = 0.0; ///< nominal shaft speed, rpm
};

/// The page. `r` must have been made with BearingCheckOptions::keep_spectra (a band without its
/// spectrum is shown as "not available").
std::string render_bearing_page(const bearing::BearingCheckResult& r, const BearingPageInfo& info);

/// Ids of the <svg> elements render_bearing_page() emits for `r`: "bearing-band-<band name>" and
/// its zoom on the cage family's range "bearing-band-<band name>-low", per band with a spectrum.
std::vector<std::string> bearing_plot_ids(const bearing::BearingCheckResult& r);

}  // namespace amb::host::report
