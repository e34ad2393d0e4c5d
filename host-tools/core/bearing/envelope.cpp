#include "host-tools/core/bearing/envelope.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace amb::host::bearing {
namespace {

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const { fftw_destroy_plan(p); }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

bool is_smooth(size_t n) {
  for (size_t p : {2u, 3u, 5u, 7u})
    while (n % p == 0) n /= p;
  return n == 1;
}

// In-place complex FFT of `buf` (interleaved re/im), sign -1 forward / +1 inverse.
void complex_fft(std::vector<std::complex<double>>& buf, int sign) {
  auto* p = reinterpret_cast<fftw_complex*>(buf.data());
  Plan plan(fftw_plan_dft_1d(static_cast<int>(buf.size()), p, p, sign, FFTW_ESTIMATE));
  fftw_execute(plan.get());
}

}  // namespace

size_t smooth_length_at_most(size_t n) {
  while (n > 1 && !is_smooth(n)) --n;
  return n;
}

double EnvelopeSpectrum::at(double f_hz) const {
  const auto k = static_cast<long>(std::llround(f_hz / df_hz));
  if (k < 0 || static_cast<size_t>(k) >= amplitude.size()) return 0.0;
  return amplitude[static_cast<size_t>(k)];
}

BandAnalyser::BandAnalyser(const std::vector<double>& x, double fs_hz) : fs_hz_(fs_hz) {
  if (!(fs_hz > 0)) throw std::invalid_argument("sample rate must be > 0");
  if (x.size() < 64) throw std::invalid_argument("record too short (< 64 samples)");
  n_ = smooth_length_at_most(x.size());
  const double mean = std::accumulate(x.begin(), x.begin() + static_cast<long>(n_), 0.0) / static_cast<double>(n_);
  std::vector<double> in(n_);
  for (size_t i = 0; i < n_; ++i) in[i] = x[i] - mean;
  std::vector<std::complex<double>> out(n_ / 2 + 1);
  Plan plan(fftw_plan_dft_r2c_1d(static_cast<int>(n_), in.data(), reinterpret_cast<fftw_complex*>(out.data()),
                                 FFTW_ESTIMATE));
  fftw_execute(plan.get());
  spec_re_.resize(out.size());
  spec_im_.resize(out.size());
  for (size_t k = 0; k < out.size(); ++k) {
    spec_re_[k] = out[k].real();
    spec_im_[k] = out[k].imag();
  }
}

std::vector<double> BandAnalyser::squared_envelope(double low_hz, double high_hz, int pad) const {
  const double df = fs_hz_ / static_cast<double>(n_);
  const auto k0 = static_cast<size_t>(std::max(1.0, std::ceil(low_hz / df)));
  const auto k1 = std::min(spec_re_.size() - 1, static_cast<size_t>(std::floor(high_hz / df)));
  if (k1 <= k0 + 4) return {};
  // Baseband: the band's positive-frequency bins moved to start at 0. Its inverse FFT is the
  // analytic band signal demodulated by a complex exponential, whose magnitude is the envelope.
  // Any length >= the bin count spans the record duration T (bins are 1/T apart), so round
  // up to a fast FFT size.
  size_t m = static_cast<size_t>(pad) * (k1 - k0);
  while (!is_smooth(m)) ++m;
  std::vector<std::complex<double>> buf(m);
  for (size_t k = k0; k < k1; ++k) buf[k - k0] = {spec_re_[k], spec_im_[k]};
  complex_fft(buf, FFTW_BACKWARD);
  std::vector<double> env(buf.size());
  // Scale so the envelope is in input units^2 regardless of n (analytic signal = 2 x positive bins).
  const double scale = 2.0 / static_cast<double>(n_);
  for (size_t i = 0; i < buf.size(); ++i) env[i] = std::norm(buf[i] * scale);
  return env;
}

double BandAnalyser::band_kurtosis(double low_hz, double high_hz) const {
  const std::vector<double> e2 = squared_envelope(low_hz, high_hz, 1);
  if (e2.empty()) return 0.0;
  double m2 = 0, m4 = 0;
  for (double v : e2) {
    m2 += v;
    m4 += v * v;
  }
  m2 /= static_cast<double>(e2.size());
  m4 /= static_cast<double>(e2.size());
  return m2 > 0 ? m4 / (m2 * m2) - 2.0 : 0.0;
}

double BandAnalyser::kurtosis_standard_error(double bandwidth_hz) const {
  // |z|^2 of complex Gaussian noise is exponential; its estimated E x^2 / (E x)^2 has variance
  // 4 / N over N independent samples (delta method), N = bandwidth x duration.
  const double n_ind = bandwidth_hz * static_cast<double>(n_) / fs_hz_;
  return n_ind > 0 ? 2.0 / std::sqrt(n_ind) : 1.0;
}

std::vector<Band> BandAnalyser::band_grid(const BandSelectionOptions& o) const {
  if (!o.valid()) throw std::invalid_argument("invalid band selection options");
  const double nyq = 0.5 * fs_hz_;
  const double top = (1.0 - o.top_guard_fraction) * nyq;
  std::vector<Band> out;
  // Grid: bandwidth nyq / 2^(l/2) rounded to the dyadic (l even) and 1/3-dyadic-like (l odd,
  // bandwidth nyq / (3 * 2^((l-1)/2)) ) levels of Antoni's fast kurtogram; centres every half
  // bandwidth (50 % overlap) so a resonance is never split across two bands. Level 0 (the whole
  // spectrum) and bands crossing the guard are clipped at `top`.
  for (int l = 0; l <= 2 * o.max_levels; ++l) {
    const double bw = (l % 2 == 0) ? nyq / std::pow(2.0, l / 2) : nyq / (1.5 * std::pow(2.0, (l - 1) / 2));
    if (bw < o.min_bandwidth_hz) break;
    for (double lo = 0.0; lo + bw <= nyq * (1.0 + 1e-9); lo += 0.5 * bw) {
      if (lo < o.min_low_edge_hz) continue;
      const double hi = std::min(lo + bw, top);
      if (hi - lo < 0.75 * bw || hi - lo < o.min_bandwidth_hz) continue;  // mostly inside the guard
      const double k = band_kurtosis(lo, hi);
      if (o.tonal_sigmas > 0 && k < -o.tonal_sigmas * kurtosis_standard_error(hi - lo)) continue;
      out.push_back(Band{lo, hi, k, l});
    }
  }
  return out;
}

Band BandAnalyser::select_band(const BandSelectionOptions& o) const {
  const auto grid = band_grid(o);
  Band best;
  best.low_hz = 0.0;
  best.high_hz = (1.0 - o.top_guard_fraction) * 0.5 * fs_hz_;
  best.kurtosis = -1e300;
  for (const auto& b : grid)
    if (b.kurtosis > best.kurtosis) best = b;
  if (grid.empty()) best.kurtosis = band_kurtosis(best.low_hz, best.high_hz);
  return best;
}

DiscreteRemoval BandAnalyser::remove_discrete_components(double halfwidth_hz, double false_alarm_probability) {
  if (!(halfwidth_hz > 0) || !(false_alarm_probability > 0 && false_alarm_probability < 1))
    throw std::invalid_argument("invalid discrete-removal options");
  DiscreteRemoval d;
  const size_t m = spec_re_.size();
  const double df = fs_hz_ / static_cast<double>(n_);
  const auto w = static_cast<long>(std::max(4.0, std::round(halfwidth_hz / df)));
  d.threshold = std::sqrt(std::log2(static_cast<double>(m) / false_alarm_probability));
  std::vector<double> mag(m), med(m);
  double total = 0.0;
  for (size_t k = 0; k < m; ++k) {
    mag[k] = std::hypot(spec_re_[k], spec_im_[k]);
    if (k > 0) total += mag[k] * mag[k];
  }
  // Running median, evaluated every `step` bins (the floor varies slowly over a window).
  const long step = std::max(1L, w / 8);
  std::vector<double> win;
  win.reserve(static_cast<size_t>(2 * w + 1));
  for (long c = 1; c < static_cast<long>(m); c += step) {
    win.clear();
    for (long j = std::max(1L, c - w); j <= std::min(static_cast<long>(m) - 1, c + w); ++j)
      win.push_back(mag[static_cast<size_t>(j)]);
    auto mid = win.begin() + static_cast<long>(win.size() / 2);
    std::nth_element(win.begin(), mid, win.end());
    for (long j = c; j < std::min(static_cast<long>(m), c + step); ++j) med[static_cast<size_t>(j)] = *mid;
  }
  double removed = 0.0;
  for (size_t k = 1; k < m; ++k) {
    if (mag[k] > d.threshold * med[k] && mag[k] > 0) {
      const double g = med[k] / mag[k];
      removed += mag[k] * mag[k] - med[k] * med[k];
      spec_re_[k] *= g;
      spec_im_[k] *= g;
      ++d.bins;
    }
  }
  d.energy_fraction = total > 0 ? removed / total : 0.0;
  return d;
}

void BandAnalyser::prewhiten() {
  for (size_t k = 0; k < spec_re_.size(); ++k) {
    const double m = std::hypot(spec_re_[k], spec_im_[k]);
    if (k == 0 || !(m > 0)) {
      spec_re_[k] = spec_im_[k] = 0.0;
      continue;
    }
    spec_re_[k] /= m;
    spec_im_[k] /= m;
  }
}

std::vector<double> BandAnalyser::magnitude() const {
  std::vector<double> m(spec_re_.size());
  for (size_t k = 0; k < m.size(); ++k) m[k] = std::hypot(spec_re_[k], spec_im_[k]);
  return m;
}

EnvelopeSpectrum BandAnalyser::envelope_spectrum(const Band& band) const {
  EnvelopeSpectrum s;
  s.band = band;
  // Pad x2: |z|^2 has twice the bandwidth of z; a band-rate sampling would alias it.
  std::vector<double> e2 = squared_envelope(band.low_hz, band.high_hz, 2);
  if (e2.empty()) return s;
  const double mean = std::accumulate(e2.begin(), e2.end(), 0.0) / static_cast<double>(e2.size());
  const size_t m = e2.size();
  std::vector<std::complex<double>> buf(m);
  double wsum = 0.0;
  for (size_t i = 0; i < m; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(m));
    wsum += w;
    buf[i] = (e2[i] - mean) * w;
  }
  complex_fft(buf, FFTW_FORWARD);
  // The envelope record spans the same duration as the input: bin spacing fs / n.
  s.df_hz = fs_hz_ / static_cast<double>(n_);
  s.amplitude.resize(m / 2);
  for (size_t k = 0; k < m / 2; ++k) s.amplitude[k] = 2.0 * std::abs(buf[k]) / wsum;
  return s;
}

}  // namespace amb::host::bearing
