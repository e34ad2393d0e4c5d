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

/// Per-channel normalisation of the peak indicator: mean |H_c|^2 over the bins where at least
/// half of the channels reach o.min_coherence inside the search band (1 where none).
std::vector<double> channel_norms(const std::vector<double>& f_hz, const std::vector<std::vector<std::complex<double>>>& h,
                                  const std::vector<std::vector<double>>& coherence, const PeakOptions& o = {});

/// A mode extracted from a multi-channel accelerance by a common-pole rational fit.
struct ModalEstimate {
  double frequency_hz = 0.0;                   ///< undamped natural frequency of the pole, Hz
  double damping_ratio = 0.0;                  ///< 1
  std::vector<std::complex<double>> shape;     ///< residue per channel (the mode shape), (m/s^2)/A
};

/// Experimental modal analysis of one band: H_c(w) = -w^2 (sum_k R_ck / (w_k^2 - w^2 + 2 i z_k w_k w)
/// + A_c) + B_c, poles common to all channels (frequencies and damping by a bounded NLopt
/// search from `start_hz`), residues and residual terms per channel by weighted linear least
/// squares. `w` [channel][bin]: weights (0: bin ignored). Applied alike to the measured and the
/// modelled FRF, it gives the modal frequencies, damping ratios and shapes compared (MAC).
std::vector<ModalEstimate> fit_modes(const std::vector<double>& f_hz, const std::vector<std::vector<std::complex<double>>>& h,
                                     const std::vector<std::vector<double>>& w, double f_lo_hz, double f_hi_hz,
                                     const std::vector<double>& start_hz);

/// Modal assurance criterion |a^H b|^2 / (|a|^2 |b|^2) of two complex shapes (same length), 0..1.
double mac(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b);

}  // namespace amb::host::residual
