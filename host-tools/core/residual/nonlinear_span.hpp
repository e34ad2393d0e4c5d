#pragma once
// Nonlinear stretches of a sweep record, detected from the time data: a rub, a backup-bearing
// contact or actuator saturation shows as broadband spikes in the accelerations far above
// the excitation band, and/or a control current close to the bias current (coil current
// near zero or twice the bias: the linearised actuator no longer holds). Such stretches are
// left out of the FRF estimate, each with its reason.
//  * Blocks of block_s (Hann, hop block_s/2); high-band energy of every accelerometer in
//    [band_lo_hz, band_hi_hz] relative to its median over the record. A block is nonlinear
//    when the mean over channels of that ratio exceeds min_ratio_db, or when the peak
//    |current| exceeds current_fraction * bias.
//  * Consecutive nonlinear blocks are merged into spans; each span is padded by guard_s.
#include <string>
#include <vector>

namespace amb::host::residual {

struct NonlinearSpan {
  double t0_s = 0.0, t1_s = 0.0;   ///< left out, s from the record start
  std::string reason;              ///< what was seen (ratio dB, current peak)
};

struct NonlinearOptions {
  double block_s = 0.0625;         ///< analysis block, s
  double band_lo_hz = 600.0, band_hi_hz = 1000.0;  ///< high band, Hz (above the fitted band)
  double min_ratio_db = 15.0;      ///< high-band energy over its median, dB
  double current_fraction = 0.8;   ///< |i| above this fraction of the bias current
  double guard_s = 0.1;            ///< padding each side, s
};

/// `current_a`: control current (A); `accel`: channels (any unit); `bias_current_a` <= 0
/// disables the current test.
std::vector<NonlinearSpan> detect_nonlinear_spans(const std::vector<double>& current_a, const std::vector<std::vector<double>>& accel,
                                                  double fs_hz, double bias_current_a, const NonlinearOptions& o = {});

}  // namespace amb::host::residual
