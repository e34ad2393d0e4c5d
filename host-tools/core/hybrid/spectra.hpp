#pragma once
// Spectral representations compared by the hybrid model (seed 001, issue 18): the log power
// spectral density (Welch) and the envelope spectrum (squared envelope of a band, Welch), on
// fixed absolute-frequency grids so that records of any sample rate land on the same bins.
#include <cstddef>
#include <string>
#include <vector>

namespace amb::host::hybrid {

/// How a record becomes the two spectra. Stored in the model file: prediction uses the
/// training settings, never its own.
///
/// Both spectra are read on a grid whose bins are max(min width, rel_bin_width x f) wide:
/// constant width at low frequency, constant percentage above. The percentage is twice the
/// relative uncertainty of the nominal speed (CWRU README: +-0.5 %), so a line predicted from
/// the nominal operating point falls in the bin of the measured line; finer detail than that
/// cannot be predicted from the operating point by any model and is not scored.
struct SpectralOptions {
  double psd_df_hz = 1.0;          ///< Welch resolution of the PSD, Hz (segment 1/df, Hann, 50 % overlap)
  double psd_min_hz = 2.0;         ///< PSD grid lower end, Hz
  double psd_max_hz = 5000.0;      ///< PSD grid upper end, Hz (record Nyquist must exceed it)
  double psd_bin_min_hz = 4.0;     ///< narrowest PSD grid bin, Hz (>= psd_df_hz)
  double env_band_low_hz = 500.0;  ///< envelope band lower edge, Hz
  double env_band_high_hz = 5000.0;  ///< envelope band upper edge, Hz
  double env_df_hz = 0.5;          ///< Welch resolution of the squared envelope's spectrum, Hz
  double env_min_hz = 2.0;         ///< envelope grid lower end, Hz (the squared envelope's DC is left out)
  double env_max_hz = 500.0;       ///< envelope grid upper end, Hz
  double env_bin_min_hz = 1.0;     ///< narrowest envelope grid bin, Hz (>= env_df_hz)
  double rel_bin_width = 0.01;     ///< relative bin width above the constant-width part (2 x speed uncertainty)
  /// Floor added to the PSD before the log, relative to the record's mean PSD over the grid
  /// (keeps empty bins of simulated spectra finite), dimensionless.
  double psd_floor_rel = 1e-9;
  bool valid(std::string* why = nullptr) const;
  /// Shortest record (s) the options can be applied to.
  double min_record_s() const;
};

/// Bin edges of a grid, Hz: bin i is [edges[i], edges[i+1]).
struct Grid {
  std::vector<double> edges;
  size_t bins() const { return edges.empty() ? 0 : edges.size() - 1; }
  double centre_hz(size_t i) const { return 0.5 * (edges[i] + edges[i + 1]); }
};
Grid psd_grid(const SpectralOptions& o);
Grid env_grid(const SpectralOptions& o);

/// The two spectra of one record (or one segment of it).
struct Spectra {
  std::vector<double> log_psd;  ///< log10 of the mean PSD in each bin (input unit^2/Hz), PSD grid
  std::vector<double> env;      ///< rms amplitude of the squared envelope in each bin (input unit^2), envelope grid
};

/// Spectra of `x` sampled at `fs_hz`. Throws std::invalid_argument if the record is shorter
/// than options.min_record_s(), fs_hz is not positive, or the Nyquist frequency is below
/// the PSD grid or the envelope band.
/// `scales`: the spectrum is averaged (power) over copies with the frequency axis scaled by
/// each factor: the expected spectrum of a simulated record when the true speed is only known
/// to within the scales (see speed_scales). {1} for a measured record.
Spectra compute_spectra(const std::vector<double>& x, double fs_hz, const SpectralOptions& o,
                        const std::vector<double>& scales = {1.0});

/// `points` speed scales spread evenly over 1 +- relative_uncertainty ({1} if either is 0 / 1).
std::vector<double> speed_scales(double relative_uncertainty, int points);

/// Split `x` into consecutive segments of `segment_s` seconds (the tail shorter than one
/// segment is dropped).
std::vector<std::vector<double>> split_segments(const std::vector<double>& x, double fs_hz, double segment_s);

/// Kinematic transport of a grid spectrum (seed 001 eq. 14-16: every bearing and shaft line is
/// at a fixed order of the shaft speed). `y` was read at speed s0; the result is `y` as it would
/// read at s1 = ratio x s0 if all of it moved with the speed: the value at bin centre f is
/// taken at f / ratio (linear interpolation between bin centres `centres_hz`, ends held).
std::vector<double> move_with_speed(const std::vector<double>& y, const std::vector<double>& centres_hz, double ratio);

/// Mean of y over +-halfwidth bins (shorter at the ends).
std::vector<double> local_mean(const std::vector<double>& y, int halfwidth);

/// Kinematic transport of a log10 PSD read at one speed to `ratio` x that speed: the local
/// mean over +-`halfwidth` bins (the transfer path: housing resonances stay at their
/// frequency) is kept, the lines above it move with the speed (move_with_speed); the result is
/// the power mean over the speed `scales` (see speed_scales).
std::vector<double> transport_log_psd(const std::vector<double>& log_psd, const std::vector<double>& centres_hz, double ratio,
                                      const std::vector<double>& scales, int halfwidth);
/// The same for an envelope spectrum in the power domain (amplitude^2): all of it moves (its
/// content is speed-locked lines over a floor).
std::vector<double> transport_env(const std::vector<double>& env_power, const std::vector<double>& centres_hz, double ratio,
                                  const std::vector<double>& scales);
/// Bin centres of a grid, Hz.
std::vector<double> centres(const Grid& g);

/// Split-half reliability of a record's two spectra under options `o`: the Pearson correlation
/// between the spectra of the record's first and second halves, and its Spearman-Brown
/// extension to the full record, r_full = 2 r / (1 + r). sqrt(r_full) bounds the correlation
/// any prediction, however good, can reach against this record's estimate (estimation
/// variance alone). Throws std::invalid_argument if a half is shorter than o.min_record_s().
struct Reliability {
  double log_psd_half = 0, env_half = 0;  ///< halves against each other
  double log_psd_full = 0, env_full = 0;  ///< Spearman-Brown, full record
};
Reliability split_half_reliability(const std::vector<double>& x, double fs_hz, const SpectralOptions& o);

/// model::signal::pearson (0 if either is constant or with fewer than 3 points). Throws
/// std::invalid_argument if the sizes differ or are < 2.
double pearson(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace amb::host::hybrid
