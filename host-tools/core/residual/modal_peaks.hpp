#pragma once
// Resonance peaks of a measured multi-channel FRF, found from the data, and the modal
// assurance criterion between measured and modelled operating shapes at those peaks.
//  * Peak indicator: the sum over channels of |H_c(f)|^2, each channel normalised by its mean
//    over the band (so every accelerometer counts), on bins where at least half of the
//    channels have coherence >= min_coherence.
//  * A peak is a local maximum over +-max(2 % of f, 1 Hz) that stands at least
//    min_prominence above the median of the indicator over +-15 % of f; its frequency is
//    refined by a parabola through the log indicator.
#include <complex>
#include <vector>

namespace amb::host::residual {

struct MeasuredPeak {
  double frequency_hz = 0.0;                   ///< refined peak frequency, Hz
  double prominence = 0.0;                     ///< indicator / local median at the peak, 1
  std::vector<std::complex<double>> shape;     ///< H per channel at the peak bin, (m/s^2)/A
};

struct PeakOptions {
  double f_min_hz = 8.0, f_max_hz = 240.0;     ///< search band, Hz
  double min_coherence = 0.8;                  ///< per-bin coherence needed (half the channels)
  double min_prominence = 3.0;                 ///< indicator / local median, 1
};

/// Peaks of `h` ([channel][bin], bins at f_hz) with coherence `coherence` ([channel][bin]).
std::vector<MeasuredPeak> find_peaks(const std::vector<double>& f_hz, const std::vector<std::vector<std::complex<double>>>& h,
                                     const std::vector<std::vector<double>>& coherence, const PeakOptions& o = {});

/// Modal assurance criterion |a^H b|^2 / (|a|^2 |b|^2) of two complex shapes (same length), 0..1.
double mac(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b);

}  // namespace amb::host::residual
