#pragma once
// Streaming short-time Fourier transform of one channel (seed 003 eq. 12-13), fed sample by
// sample or in blocks. All memory and the FFTW plan are made in configure(); push() then
// runs in bounded time and never allocates.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "model/signal/window_function.hpp"

namespace amb::model::signal {

/// STFT settings. Defaults are seed 003's: Hamming 0.5 s, 90 % overlap, 8192 points.
struct StftOptions {
  double sample_rate_hz = 10000.0;   ///< input sample rate, Hz; (0, 1e7]
  WindowType window = WindowType::kHamming;
  double window_s = 0.5;             ///< window duration T, s; window_s*fs in [16, nfft] samples
  double overlap = 0.9;              ///< overlap fraction of consecutive windows; [0, 0.99]
  size_t nfft = 8192;                ///< FFT length (zero padded); power of two in [64, 1048576]

  /// Empty if valid; otherwise a message naming the bad field and its allowed range.
  std::string validate() const;
  /// Window length in samples, round(window_s * sample_rate_hz).
  size_t window_samples() const;
  /// Hop between frames in samples, max(1, round(window_samples * (1 - overlap))).
  size_t hop_samples() const;
};

/// Streaming STFT. Not copyable (it owns an FFTW plan); configure() may be called again.
class StreamingStft {
 public:
  StreamingStft() = default;
  ~StreamingStft();
  StreamingStft(const StreamingStft&) = delete;
  StreamingStft& operator=(const StreamingStft&) = delete;

  /// Allocates buffers, builds the window and the FFTW r2c plan (FFTW_ESTIMATE). Returns an
  /// empty string on success, else the validation message (and stays unconfigured).
  /// Plan creation is serialised internally (the FFTW planner is not thread-safe).
  std::string configure(const StftOptions& options);
  bool configured() const { return plan_ != nullptr; }
  const StftOptions& options() const { return options_; }

  /// Clears the sample history (keeps the plan and buffers). Next frame after a full window.
  void reset();

  /// Time warp for the following frames (computed order tracking): the relative rate
  /// kappa = (d f / d t) / f of the tracked speed at the frame centre, 1/s. Each frame is
  /// then resampled (cubic interpolation) onto a uniform grid of the shaft angle predicted
  /// by f(t) = f_c (1 + kappa (t - t_c)), so every order line of a linearly accelerating
  /// shaft becomes stationary at its value at the frame centre instead of smearing over
  /// kappa * f_c * T. 0 disables the warp (plain STFT). Clamped to |kappa| <= 1.6 / T so the
  /// predicted speed stays above 20 % of f_c over the window. No allocation.
  void set_warp_rate(double kappa_per_s);
  /// Recompute the newest frame with another warp rate (see set_warp_rate), e.g. to test
  /// several chirp rates on the same samples. Returns false if no frame exists yet.
  /// Bounded time, no allocation.
  bool recompute(double kappa_per_s);
  double warp_rate() const { return warp_kappa_; }
  /// Heap bytes this STFT holds after configure(): window, history, power spectrum and the
  /// FFTW input/output buffers (the plan's own memory is FFTW's and not counted).
  size_t heap_bytes() const;

  /// Push one sample (input units, e.g. g or m). Returns true if this sample completed a
  /// frame; power() then holds that frame. Bounded time, no allocation.
  bool push(double x);

  /// One-sided power spectrum of the newest frame, nfft/2+1 bins, (input unit)^2, scaled so
  /// that a stationary sine of amplitude A gives a peak of about A^2 (window gain removed).
  /// The frame is demeaned before windowing (seed 003: "demeaned raw vibration signal").
  std::span<const double> power() const { return power_; }
  /// Bin spacing of power(), Hz (= fs / nfft).
  double bin_hz() const { return bin_hz_; }
  /// Time of the centre of the newest frame, s, counted from the first pushed sample (t = 0)
  /// after configure()/reset(). The estimate describes the signal around this instant.
  double frame_centre_s() const { return frame_centre_s_; }
  /// Number of frames computed since configure()/reset().
  uint64_t frames() const { return frames_; }
  /// Samples pushed since configure()/reset().
  uint64_t samples() const { return samples_; }

 private:
  void compute_frame();
  double sample_at(double u) const;  // history at fractional index u (0 = oldest), cubic
  void release();

  StftOptions options_{};
  size_t window_len_ = 0;
  size_t hop_ = 0;
  std::vector<double> window_;     // window_len_
  std::vector<double> history_;    // ring of the last window_len_ samples
  std::vector<double> power_;      // nfft/2 + 1
  size_t write_pos_ = 0;
  uint64_t samples_ = 0;
  uint64_t frames_ = 0;
  size_t since_frame_ = 0;
  double bin_hz_ = 0.0;
  double power_scale_ = 0.0;
  double frame_centre_s_ = 0.0;
  double warp_kappa_ = 0.0;
  double* fft_in_ = nullptr;       // fftw_malloc'd, nfft
  void* fft_out_ = nullptr;        // fftw_complex[nfft/2+1]
  void* plan_ = nullptr;           // fftw_plan
};

}  // namespace amb::model::signal
