#pragma once
// Shaft speed refined from the record: the comb of shaft harmonics k f_r (k = 1..harmonics) in
// the magnitude spectrum, searched over nominal x [1 - range, 1 + range].
//
// Each harmonic's bin is compared with the median of the bins within +-5 Hz (Rayleigh under
// Gaussian noise: P(ratio > r) = 2^(-r^2)); the harmonics are Fisher-combined and the comb with
// the smallest p over the search grid wins. The refinement is used when that p, Bonferroni-
// corrected for the independent comb positions tried, is below `false_alarm` and the comb has its
// 1x line and at least one more harmonic present on their own (p < 0.01); otherwise the
// nominal speed is kept and the caller must allow for its uncertainty. Harmonics that lie on a
// defect line (`excluded_orders`, e.g. BPFO / f_r and its multiples) are left out of the comb:
// such a line cannot tell the shaft from the defect (the 6200's BPFO = 3.05 f_r made an outer-
// race record's envelope spectrum refine the speed to BPFO / 3, 1.6 % off the true speed).
#include <vector>

namespace amb::host::bearing {

struct SpeedRefinement {
  double nominal_hz = 0.0;  ///< speed given (file or command line), Hz
  double speed_hz = 0.0;    ///< refined speed (nominal if not refined), Hz
  double log10_p = 0.0;     ///< corrected log10 p of the best comb (<= 0)
  int harmonics_present = 0;  ///< harmonics of the best comb with their own p < 0.01
  int harmonics_used = 0;     ///< harmonics in the comb (those on a defect line left out)
  bool refined = false;     ///< speed_hz comes from the record
};

/// @param magnitude   one-sided magnitude spectrum, bin k at k * df_hz
/// @param df_hz       bin spacing, Hz (> 0)
/// @param nominal_hz  nominal shaft speed, Hz (> 0)
/// @param range       relative search range (0.02: +-2 %)
/// @param harmonics   harmonics in the comb (>= 1)
/// @param false_alarm corrected p below which the refinement is used
/// @param excluded_orders multiples of the shaft speed where another line family may sit (orders, > 0)
/// @param excluded_tolerance a harmonic h is left out when |h - order| <= tolerance x order for any of them
SpeedRefinement refine_speed(const std::vector<double>& magnitude, double df_hz, double nominal_hz, double range = 0.02,
                             int harmonics = 8, double false_alarm = 1e-3, const std::vector<double>& excluded_orders = {},
                             double excluded_tolerance = 0.0);

}  // namespace amb::host::bearing
