#pragma once
// Envelope analysis for rolling-bearing diagnosis: resonance-band selection by a
// "kurtogram-lite" (spectral kurtosis of the complex band envelope over a dyadic and
// 1/3-dyadic grid of bands), Hilbert envelope via FFT, envelope spectrum.
#include <cstddef>
#include <vector>

namespace amb::host::bearing {

/// A frequency band and its spectral kurtosis.
struct Band {
  double low_hz = 0.0;       ///< lower edge, Hz
  double high_hz = 0.0;      ///< upper edge, Hz
  double kurtosis = 0.0;     ///< E|z|^4 / (E|z|^2)^2 - 2 of the complex band envelope z (0 for Gaussian noise)
  int level = 0;             ///< grid level (bandwidth = fs/2 / 2^(level/2) ... see .cpp)
};

/// Options of the band selection.
struct BandSelectionOptions {
  double min_bandwidth_hz = 500.0;  ///< narrowest band considered, Hz (must pass the sidebands of the highest line of interest)
  double min_low_edge_hz = 0.0;     ///< bands starting below this are skipped, Hz
  int max_levels = 8;               ///< depth of the band grid (each level narrows by sqrt(2)...2)
  /// Bands reaching into the top `top_guard_fraction` of [0, Nyquist] are skipped: that is where
  /// anti-alias filters roll off and converters put their artefacts (a 48 kHz record's
  /// 22.5-24 kHz band with spectral kurtosis 4900 and no defect lines, issue 15). [0, 0.5)
  double top_guard_fraction = 0.15;
  /// Tonal guard: a band whose spectral kurtosis is below -tonal_sigmas x its standard error
  /// under Gaussian noise (2 / sqrt(bandwidth x duration)) is dominated by a few discrete tones;
  /// its envelope holds their beats, not modulation. Skipped. <= 0 disables the guard.
  double tonal_sigmas = 3.0;
  bool valid() const {
    return min_bandwidth_hz > 0 && min_low_edge_hz >= 0 && max_levels >= 1 && top_guard_fraction >= 0 &&
           top_guard_fraction < 0.5;
  }
};

/// Envelope spectrum of a signal in one band.
struct EnvelopeSpectrum {
  std::vector<double> amplitude;  ///< one-sided amplitude of the squared envelope's spectrum (Hann window), input unit^2
  double df_hz = 0.0;             ///< bin spacing, Hz (bin k is at k * df_hz)
  Band band;                      ///< band used
  /// Amplitude at frequency f_hz (nearest bin), 0 outside the spectrum.
  double at(double f_hz) const;
};

/// What remove_discrete_components() did.
struct DiscreteRemoval {
  size_t bins = 0;               ///< spectrum bins edited
  double energy_fraction = 0.0;  ///< share of the record's energy removed, 0..1
  double threshold = 0.0;        ///< k: a bin is discrete if |X| > k x local median
};

/// Precomputed spectrum of a record; bands are analysed from it without recomputing the FFT.
class BandAnalyser {
 public:
  /// @param x      samples (any unit); the mean is removed; the record is trimmed to the
  ///               longest 2^a 3^b 5^c 7^d length so the FFT stays fast
  /// @param fs_hz  sample rate, Hz (> 0)
  BandAnalyser(const std::vector<double>& x, double fs_hz);
  /// Spectral kurtosis of the band [low_hz, high_hz).
  double band_kurtosis(double low_hz, double high_hz) const;
  /// The band with the highest spectral kurtosis on the grid (kurtogram-lite), guards applied.
  Band select_band(const BandSelectionOptions& o) const;
  /// Every band of the grid that passes the guards (top of the spectrum, tonal), with its SK.
  std::vector<Band> band_grid(const BandSelectionOptions& o) const;
  /// Standard error of band_kurtosis() under Gaussian noise for a band `bandwidth_hz` wide.
  double kurtosis_standard_error(double bandwidth_hz) const;
  /// Remove discrete (deterministic) components from the stored spectrum before band selection:
  /// a bin whose magnitude exceeds k times the median magnitude of the bins within
  /// +-halfwidth_hz is set to that median (phase kept). Under Gaussian noise |X| is Rayleigh,
  /// P(|X| > k median) = 2^(-k^2); k = sqrt(log2(n_bins / p_fa)) allows p_fa false edits per record.
  /// Caveat (docs/bearing.md): a fault whose impacts are strictly periodic (no slip) is itself
  /// discrete and is attenuated too.
  DiscreteRemoval remove_discrete_components(double halfwidth_hz, double false_alarm_probability);
  /// Cepstrum pre-whitening (Sawalhi & Randall; Borghesani et al. 2013): every bin of the stored
  /// spectrum is set to unit magnitude, its phase kept (the real cepstrum edited to zero at all
  /// quefrencies but 0). Discrete lines (shaft harmonics, tones) and the transfer path's
  /// colouring are flattened; impulsive content keeps its phase alignment and stays impulsive.
  /// Bins of zero magnitude stay zero.
  void prewhiten();
  /// Magnitude of the stored spectrum, bin k at k * fs / length() Hz (k = 0 .. length()/2).
  std::vector<double> magnitude() const;
  /// Envelope spectrum for `band` (squared envelope, mean removed, Hann window).
  EnvelopeSpectrum envelope_spectrum(const Band& band) const;
  double fs_hz() const { return fs_hz_; }
  size_t length() const { return n_; }

 private:
  // Complex baseband signal (bins of [low, high) shifted to 0), zero-padded by `pad`.
  std::vector<double> squared_envelope(double low_hz, double high_hz, int pad) const;
  size_t n_ = 0;
  double fs_hz_ = 0.0;
  std::vector<double> spec_re_, spec_im_;  // one-sided spectrum, n/2 + 1 bins
};

/// Largest length <= n whose prime factors are all in {2, 3, 5, 7}.
size_t smooth_length_at_most(size_t n);

}  // namespace amb::host::bearing
