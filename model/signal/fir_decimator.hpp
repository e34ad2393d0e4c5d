#pragma once
// Anti-alias low-pass FIR + integer decimation, streaming. Windowed-sinc (Blackman) design,
// linear phase: the output lags the input by (taps-1)/2 input samples, which delay_s()
// reports so callers can keep time stamps right. configure() allocates; push() does not.
#include <cstddef>
#include <string>
#include <vector>

namespace amb::model::signal {

/// Settings of the decimator.
struct FirDecimatorOptions {
  double input_rate_hz = 97656.0;  ///< input sample rate, Hz; > 0
  size_t factor = 8;               ///< decimation factor M; [1, 4096] (1: pass-through)
  /// Cut-off as a fraction of the output Nyquist frequency fs/(2M); (0.1, 0.95].
  /// Components above it are attenuated by the Blackman sinc (> 70 dB stop band beyond
  /// the transition band of about 5.5 * fs_in / taps).
  double cutoff_fraction = 0.8;
  /// Taps per unit of decimation factor (taps = taps_per_factor * M + 1); [4, 64].
  size_t taps_per_factor = 16;

  /// Empty if valid; otherwise a message naming the bad field and its allowed range.
  std::string validate() const;
};

/// Streaming decimator.
class FirDecimator {
 public:
  /// Validate, design the filter, allocate. Empty string on success, else the message.
  std::string configure(const FirDecimatorOptions& options);
  /// Forget the history.
  void reset();
  /// Push one input sample; returns true and sets `out` every M-th sample. No allocation.
  bool push(double x, double& out);
  /// Output sample rate, Hz.
  double output_rate_hz() const { return options_.input_rate_hz / static_cast<double>(options_.factor); }
  /// Group delay of the filter, s (output sample k describes input time k*M/fs_in - delay_s).
  double delay_s() const;
  size_t taps() const { return taps_.size(); }

 private:
  FirDecimatorOptions options_{};
  std::vector<double> taps_;
  std::vector<double> history_;  // 2 * taps, mirrored so the dot product is contiguous
  size_t pos_ = 0;
  size_t phase_ = 0;
};

}  // namespace amb::model::signal
