#include "model/signal/streaming_stft.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <mutex>

namespace amb::model::signal {
namespace {
// The FFTW planner (plan creation/destruction) is not thread-safe; execution is.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}
bool is_power_of_two(size_t n) { return n != 0 && (n & (n - 1)) == 0; }
}  // namespace

std::string StftOptions::validate() const {
  if (!(sample_rate_hz > 0.0 && sample_rate_hz <= 1e7))
    return "sample_rate_hz must be in (0, 1e7] Hz, got " + std::to_string(sample_rate_hz);
  if (!is_power_of_two(nfft) || nfft < 64 || nfft > (size_t{1} << 20))
    return "nfft must be a power of two in [64, 1048576], got " + std::to_string(nfft);
  if (!(window_s > 0.0) || !std::isfinite(window_s))
    return "window_s must be > 0 s, got " + std::to_string(window_s);
  const size_t len = window_samples();
  if (len < 16 || len > nfft)
    return "window_s * sample_rate_hz must be in [16, nfft=" + std::to_string(nfft) +
           "] samples, got " + std::to_string(len) + " (window_s " + std::to_string(window_s) +
           " s at " + std::to_string(sample_rate_hz) + " Hz)";
  if (!(overlap >= 0.0 && overlap <= 0.99))
    return "overlap must be in [0, 0.99], got " + std::to_string(overlap);
  return {};
}

size_t StftOptions::window_samples() const {
  const double n = std::round(window_s * sample_rate_hz);
  return n > 0.0 && n < 1e9 ? static_cast<size_t>(n) : 0;
}

size_t StftOptions::hop_samples() const {
  const double h = std::round(static_cast<double>(window_samples()) * (1.0 - overlap));
  return h < 1.0 ? 1 : static_cast<size_t>(h);
}

StreamingStft::~StreamingStft() { release(); }

void StreamingStft::release() {
  std::lock_guard<std::mutex> lock(planner_mutex());
  if (plan_ != nullptr) fftw_destroy_plan(static_cast<fftw_plan>(plan_));
  if (fft_in_ != nullptr) fftw_free(fft_in_);
  if (fft_out_ != nullptr) fftw_free(fft_out_);
  plan_ = nullptr;
  fft_in_ = nullptr;
  fft_out_ = nullptr;
}

std::string StreamingStft::configure(const StftOptions& options) {
  release();
  if (std::string err = options.validate(); !err.empty()) return err;
  options_ = options;
  window_len_ = options.window_samples();
  hop_ = options.hop_samples();
  const size_t n = options.nfft;
  window_.assign(window_len_, 0.0);
  fill_window(options.window, window_);
  history_.assign(window_len_, 0.0);
  power_.assign(n / 2 + 1, 0.0);
  bin_hz_ = options.sample_rate_hz / static_cast<double>(n);
  double sum_w = 0.0;
  for (double v : window_) sum_w += v;
  // |X(f)| of a sine of amplitude A is A*sum(w)/2 at the peak: scale to A^2.
  power_scale_ = 4.0 / (sum_w * sum_w);
  {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fft_in_ = static_cast<double*>(fftw_malloc(sizeof(double) * n));
    fft_out_ = fftw_malloc(sizeof(fftw_complex) * (n / 2 + 1));
    plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(n), fft_in_,
                                 static_cast<fftw_complex*>(fft_out_), FFTW_ESTIMATE);
  }
  if (plan_ == nullptr) {
    release();
    return "FFTW could not create an r2c plan for nfft " + std::to_string(n);
  }
  for (size_t i = 0; i < n; ++i) fft_in_[i] = 0.0;
  reset();
  return {};
}

void StreamingStft::reset() {
  for (double& v : history_) v = 0.0;
  write_pos_ = 0;
  samples_ = 0;
  frames_ = 0;
  since_frame_ = 0;
  frame_centre_s_ = 0.0;
  warp_kappa_ = 0.0;
}

bool StreamingStft::push(double x) {
  if (plan_ == nullptr) return false;
  history_[write_pos_] = x;
  write_pos_ = write_pos_ + 1 == window_len_ ? 0 : write_pos_ + 1;
  ++samples_;
  if (samples_ < window_len_) return false;
  if (samples_ > window_len_ && ++since_frame_ < hop_) return false;
  since_frame_ = 0;
  compute_frame();
  return true;
}

void StreamingStft::set_warp_rate(double kappa_per_s) {
  const double limit = 1.6 / options_.window_s;
  warp_kappa_ = std::isfinite(kappa_per_s) ? std::clamp(kappa_per_s, -limit, limit) : 0.0;
}

bool StreamingStft::recompute(double kappa_per_s) {
  if (plan_ == nullptr || frames_ == 0) return false;
  set_warp_rate(kappa_per_s);
  --frames_;  // compute_frame() counts the frame again
  compute_frame();
  return true;
}

double StreamingStft::sample_at(double u) const {
  // Catmull-Rom cubic through the 4 neighbours; indices clamped at the frame edges.
  const auto n = static_cast<std::ptrdiff_t>(window_len_);
  const double fl = std::floor(u);
  const double a = u - fl;
  const auto i1 = static_cast<std::ptrdiff_t>(fl);
  auto at = [&](std::ptrdiff_t i) {
    i = std::clamp<std::ptrdiff_t>(i, 0, n - 1);
    size_t k = write_pos_ + static_cast<size_t>(i);
    if (k >= window_len_) k -= window_len_;
    return history_[k];
  };
  const double p0 = at(i1 - 1), p1 = at(i1), p2 = at(i1 + 1), p3 = at(i1 + 2);
  return p1 + 0.5 * a * (p2 - p0 + a * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + a * (3.0 * (p1 - p2) + p3 - p0)));
}

void StreamingStft::compute_frame() {
  // Oldest sample sits at write_pos_ (the ring is full). Resample (if warping), demean,
  // window, zero-pad.
  if (warp_kappa_ == 0.0) {
    size_t src = write_pos_;
    for (size_t i = 0; i < window_len_; ++i) {
      fft_in_[i] = history_[src];
      src = src + 1 == window_len_ ? 0 : src + 1;
    }
  } else {
    // Warped time tau(u) = u + k u^2 / 2 (u: samples from the centre, k per sample) is the
    // predicted shaft angle in units of centre-speed samples. Its span over the window has
    // the same length as the window, shifted by k c^2 / 2; sample it uniformly and invert.
    const double c = 0.5 * static_cast<double>(window_len_ - 1);
    const double k = warp_kappa_ / options_.sample_rate_hz;
    const double tau0 = -c + 0.5 * k * c * c;
    for (size_t i = 0; i < window_len_; ++i) {
      const double tau = tau0 + static_cast<double>(i);
      const double u = 2.0 * tau / (1.0 + std::sqrt(std::max(1e-12, 1.0 + 2.0 * k * tau)));
      fft_in_[i] = sample_at(u + c);
    }
  }
  double mean = 0.0;
  for (size_t i = 0; i < window_len_; ++i) mean += fft_in_[i];
  mean /= static_cast<double>(window_len_);
  for (size_t i = 0; i < window_len_; ++i) fft_in_[i] = (fft_in_[i] - mean) * window_[i];
  // fft_in_[window_len_..nfft) stays zero: FFTW r2c out-of-place leaves the input intact.
  fftw_execute_dft_r2c(static_cast<fftw_plan>(plan_), fft_in_,
                       static_cast<fftw_complex*>(fft_out_));
  const auto* out = static_cast<const fftw_complex*>(fft_out_);
  for (size_t k = 0; k < power_.size(); ++k)
    power_[k] = power_scale_ * (out[k][0] * out[k][0] + out[k][1] * out[k][1]);
  ++frames_;
  const double centre_index =
      static_cast<double>(samples_ - window_len_) + 0.5 * static_cast<double>(window_len_ - 1);
  frame_centre_s_ = centre_index / options_.sample_rate_hz;
}

size_t StreamingStft::heap_bytes() const {
  const size_t vectors = sizeof(double) * (window_.capacity() + history_.capacity() + power_.capacity());
  const size_t n = options_.nfft;
  const size_t fft = fft_in_ != nullptr ? sizeof(double) * n + 2 * sizeof(double) * (n / 2 + 1) : 0;
  return vectors + fft;
}

}  // namespace amb::model::signal
