#include "host-tools/core/hybrid/spectra.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <mutex>
#include <numeric>
#include <stdexcept>

#include "model/signal/pearson.hpp"

namespace amb::host::hybrid {
namespace {

// FFTW's planner is not thread-safe; execution of distinct plans is. Training simulates and
// analyses on two threads, so plan creation and destruction go through this lock.
std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}
struct PlanDeleter {
  void operator()(fftw_plan_s* p) const {
    std::lock_guard<std::mutex> lock(planner_mutex());
    fftw_destroy_plan(p);
  }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

Plan plan_r2c(int n, double* in, std::complex<double>* out) {
  std::lock_guard<std::mutex> lock(planner_mutex());
  return Plan(fftw_plan_dft_r2c_1d(n, in, reinterpret_cast<fftw_complex*>(out), FFTW_ESTIMATE));
}
Plan plan_c2c(int n, std::complex<double>* buf, int sign) {
  std::lock_guard<std::mutex> lock(planner_mutex());
  auto* p = reinterpret_cast<fftw_complex*>(buf);
  return Plan(fftw_plan_dft_1d(n, p, p, sign, FFTW_ESTIMATE));
}

// Welch power spectrum of x (mean removed per segment), Hann window, 50 % overlap, segment
// length nseg. Returns the one-sided density (unit^2/Hz) on bins k * fs / nseg.
std::vector<double> welch_density(const std::vector<double>& x, double fs_hz, size_t nseg) {
  const size_t hop = nseg / 2;
  std::vector<double> w(nseg), in(nseg), acc(nseg / 2 + 1, 0.0);
  std::vector<std::complex<double>> out(nseg / 2 + 1);
  double w2 = 0.0;
  for (size_t i = 0; i < nseg; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(nseg));
    w2 += w[i] * w[i];
  }
  Plan plan = plan_r2c(static_cast<int>(nseg), in.data(), out.data());
  size_t count = 0;
  for (size_t start = 0; start + nseg <= x.size(); start += hop, ++count) {
    const double mean = std::accumulate(x.begin() + static_cast<long>(start),
                                        x.begin() + static_cast<long>(start + nseg), 0.0) /
                        static_cast<double>(nseg);
    for (size_t i = 0; i < nseg; ++i) in[i] = (x[start + i] - mean) * w[i];
    fftw_execute(plan.get());
    for (size_t k = 0; k < out.size(); ++k) acc[k] += std::norm(out[k]);
  }
  const double scale = 2.0 / (fs_hz * w2 * static_cast<double>(std::max<size_t>(count, 1)));
  for (double& a : acc) a *= scale;
  acc.front() *= 0.5;
  if (nseg % 2 == 0) acc.back() *= 0.5;
  return acc;
}

// Grid with bins max(min_width, rel x f) wide from lo to hi (the last bin ends at hi).
Grid make_grid(double lo, double hi, double min_width, double rel) {
  Grid g;
  double f = lo;
  g.edges.push_back(f);
  while (f < hi - 1e-9) {
    f = std::min(hi, f + std::max(min_width, rel * f));
    if (hi - f < 0.5 * std::max(min_width, rel * f)) f = hi;  // no sliver at the top
    g.edges.push_back(f);
  }
  return g;
}

// Sum (or mean) of fine-bin values (bin k at k df) whose centre lies in each grid bin, with
// the fine spectrum's frequency axis scaled by `scale` (a record at (1 + e) x the speed).
// Densities (mean) are divided by the scale so that the power is kept.
std::vector<double> aggregate(const std::vector<double>& fine, double df, const Grid& g, bool mean, double scale) {
  std::vector<double> out(g.bins(), 0.0);
  const double dfs = df * scale;
  for (size_t i = 0; i < g.bins(); ++i) {
    const auto k0 = static_cast<size_t>(std::ceil(g.edges[i] / dfs - 1e-9));
    const auto k1 = std::min(fine.size(), static_cast<size_t>(std::ceil(g.edges[i + 1] / dfs - 1e-9)));
    double acc = 0.0;
    size_t n = 0;
    for (size_t k = k0; k < k1; ++k, ++n) acc += fine[k];
    if (n == 0) {  // bin narrower than the resolution: nearest fine bin
      const auto k = std::min(fine.size() - 1, static_cast<size_t>(std::llround(g.centre_hz(i) / dfs)));
      acc = fine[k];
      n = 1;
    }
    out[i] = mean ? acc / (static_cast<double>(n) * scale) : acc;
  }
  return out;
}

// Average of aggregate() over the speed scales (power domain).
std::vector<double> aggregate_scaled(const std::vector<double>& fine, double df, const Grid& g, bool mean,
                                     const std::vector<double>& scales) {
  std::vector<double> acc(g.bins(), 0.0);
  for (double sc : scales) {
    const auto a = aggregate(fine, df, g, mean, sc);
    for (size_t i = 0; i < acc.size(); ++i) acc[i] += a[i] / static_cast<double>(scales.size());
  }
  return acc;
}

}  // namespace

bool SpectralOptions::valid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(psd_df_hz > 0) || !(psd_bin_min_hz >= psd_df_hz)) return fail("0 < psd_df_hz <= psd_bin_min_hz");
  if (!(psd_min_hz >= 0) || !(psd_max_hz > psd_min_hz + 10 * psd_bin_min_hz))
    return fail("psd_max_hz must exceed psd_min_hz by 10 bins");
  if (!(env_df_hz > 0) || !(env_bin_min_hz >= env_df_hz)) return fail("0 < env_df_hz <= env_bin_min_hz");
  if (!(env_min_hz >= 0) || !(env_max_hz > env_min_hz + 10 * env_bin_min_hz))
    return fail("env_max_hz must exceed env_min_hz by 10 bins");
  if (!(env_band_low_hz >= 0) || !(env_band_high_hz > env_band_low_hz + 2 * env_max_hz))
    return fail("envelope band must be wider than 2 x env_max_hz");
  if (!(rel_bin_width >= 0) || !(rel_bin_width < 0.5)) return fail("0 <= rel_bin_width < 0.5");
  if (!(psd_floor_rel > 0)) return fail("psd_floor_rel > 0");
  return true;
}

double SpectralOptions::min_record_s() const { return 1.0 / std::min(psd_df_hz, env_df_hz); }

Grid psd_grid(const SpectralOptions& o) { return make_grid(o.psd_min_hz, o.psd_max_hz, o.psd_bin_min_hz, o.rel_bin_width); }
Grid env_grid(const SpectralOptions& o) { return make_grid(o.env_min_hz, o.env_max_hz, o.env_bin_min_hz, o.rel_bin_width); }

std::vector<double> speed_scales(double relative_uncertainty, int points) {
  if (!(relative_uncertainty >= 0) || !(relative_uncertainty < 0.5)) throw std::invalid_argument("speed uncertainty in [0, 0.5)");
  if (relative_uncertainty == 0 || points <= 1) return {1.0};
  std::vector<double> s(static_cast<size_t>(points));
  for (int i = 0; i < points; ++i)
    s[static_cast<size_t>(i)] = 1.0 + relative_uncertainty * (2.0 * i / (points - 1) - 1.0);
  return s;
}

Spectra compute_spectra(const std::vector<double>& x, double fs_hz, const SpectralOptions& o,
                        const std::vector<double>& scales) {
  if (scales.empty()) throw std::invalid_argument("no speed scale");
  for (double sc : scales)
    if (!(sc > 0.5) || !(sc < 2.0)) throw std::invalid_argument("speed scale out of (0.5, 2)");
  std::string why;
  if (!o.valid(&why)) throw std::invalid_argument("spectral options: " + why);
  if (!(fs_hz > 0)) throw std::invalid_argument("sample rate must be > 0");
  if (fs_hz / 2 < o.psd_max_hz || fs_hz / 2 < o.env_band_high_hz)
    throw std::invalid_argument("sample rate " + std::to_string(fs_hz) + " Hz: Nyquist below the spectral grid (" +
                                std::to_string(std::max(o.psd_max_hz, o.env_band_high_hz)) + " Hz)");
  if (static_cast<double>(x.size()) / fs_hz < o.min_record_s())
    throw std::invalid_argument("record shorter than " + std::to_string(o.min_record_s()) + " s");
  Spectra s;
  // Log PSD.
  {
    const auto nseg = static_cast<size_t>(std::llround(fs_hz / o.psd_df_hz));
    const auto d = welch_density(x, fs_hz, nseg);
    auto p = aggregate_scaled(d, fs_hz / static_cast<double>(nseg), psd_grid(o), true, scales);
    const double mean = std::accumulate(p.begin(), p.end(), 0.0) / static_cast<double>(p.size());
    const double floor = std::max(mean * o.psd_floor_rel, 1e-300);
    s.log_psd.resize(p.size());
    for (size_t k = 0; k < p.size(); ++k) s.log_psd[k] = std::log10(p[k] + floor);
  }
  // Envelope spectrum: analytic signal of the band (positive bins only, doubled), squared
  // magnitude, then a Welch amplitude spectrum of that squared envelope.
  {
    const size_t n = x.size();
    std::vector<std::complex<double>> buf(n);
    const double mean = std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(n);
    for (size_t i = 0; i < n; ++i) buf[i] = {x[i] - mean, 0.0};
    {
      Plan fwd = plan_c2c(static_cast<int>(n), buf.data(), FFTW_FORWARD);
      fftw_execute(fwd.get());
    }
    const double df = fs_hz / static_cast<double>(n);
    for (size_t k = 0; k < n; ++k) {
      const double f = static_cast<double>(k) * df;
      const bool in_band = k <= n / 2 && f >= o.env_band_low_hz && f < o.env_band_high_hz;
      buf[k] = in_band ? 2.0 * buf[k] : std::complex<double>(0.0, 0.0);
    }
    {
      Plan inv = plan_c2c(static_cast<int>(n), buf.data(), FFTW_BACKWARD);
      fftw_execute(inv.get());
    }
    std::vector<double> e(n);
    const double inv_n = 1.0 / static_cast<double>(n);
    for (size_t i = 0; i < n; ++i) e[i] = std::norm(buf[i] * inv_n);
    const auto nseg = static_cast<size_t>(std::llround(fs_hz / o.env_df_hz));
    auto d = welch_density(e, fs_hz, nseg);
    // Density x bin width = power per fine bin; summed over a grid bin and rooted: the rms
    // amplitude of what the grid bin holds (a line counts fully whatever the bin width).
    const double bin = fs_hz / static_cast<double>(nseg);
    for (double& v : d) v *= bin;
    s.env = aggregate_scaled(d, bin, env_grid(o), false, scales);
    for (double& v : s.env) v = std::sqrt(v);
  }
  return s;
}

std::vector<std::vector<double>> split_segments(const std::vector<double>& x, double fs_hz, double segment_s) {
  if (!(fs_hz > 0) || !(segment_s > 0)) throw std::invalid_argument("split_segments: fs and segment length must be > 0");
  const auto n = static_cast<size_t>(std::llround(fs_hz * segment_s));
  std::vector<std::vector<double>> out;
  for (size_t start = 0; n > 0 && start + n <= x.size(); start += n)
    out.emplace_back(x.begin() + static_cast<long>(start), x.begin() + static_cast<long>(start + n));
  return out;
}

std::vector<double> move_with_speed(const std::vector<double>& y, const std::vector<double>& c, double ratio) {
  if (y.size() != c.size() || y.empty()) throw std::invalid_argument("move_with_speed: spectrum and centres differ in size");
  if (!(ratio > 0.2) || !(ratio < 5.0)) throw std::invalid_argument("move_with_speed: speed ratio out of (0.2, 5)");
  std::vector<double> out(y.size());
  for (size_t k = 0; k < y.size(); ++k) {
    const double f = c[k] / ratio;
    if (f <= c.front()) {
      out[k] = y.front();
    } else if (f >= c.back()) {
      out[k] = y.back();
    } else {
      const auto j = static_cast<size_t>(std::upper_bound(c.begin(), c.end(), f) - c.begin());  // c[j-1] < f <= c[j]
      const double t = (f - c[j - 1]) / (c[j] - c[j - 1]);
      out[k] = (1.0 - t) * y[j - 1] + t * y[j];
    }
  }
  return out;
}

std::vector<double> local_mean(const std::vector<double>& y, int halfwidth) {
  const auto n = static_cast<long>(y.size());
  const long h = std::max(0, halfwidth);
  std::vector<double> out(y.size());
  for (long k = 0; k < n; ++k) {
    const long lo = std::max(0L, k - h), hi = std::min(n - 1, k + h);
    double m = 0.0;
    for (long j = lo; j <= hi; ++j) m += y[static_cast<size_t>(j)];
    out[static_cast<size_t>(k)] = m / static_cast<double>(hi - lo + 1);
  }
  return out;
}

Reliability split_half_reliability(const std::vector<double>& x, double fs_hz, const SpectralOptions& o) {
  const size_t n = x.size() / 2;
  if (!(fs_hz > 0) || static_cast<double>(n) / fs_hz < o.min_record_s())
    throw std::invalid_argument("split-half reliability: each half must be at least " + std::to_string(o.min_record_s()) + " s");
  const std::vector<double> a(x.begin(), x.begin() + static_cast<long>(n)), b(x.begin() + static_cast<long>(n), x.begin() + static_cast<long>(2 * n));
  const auto sa = compute_spectra(a, fs_hz, o), sb = compute_spectra(b, fs_hz, o);
  Reliability r;
  r.log_psd_half = pearson(sa.log_psd, sb.log_psd);
  r.env_half = pearson(sa.env, sb.env);
  auto sb_ext = [](double h) { return h > -1.0 ? 2.0 * h / (1.0 + h) : -1.0; };
  r.log_psd_full = sb_ext(r.log_psd_half);
  r.env_full = sb_ext(r.env_half);
  return r;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 2) throw std::invalid_argument("pearson: sizes differ or < 2");
  return model::signal::pearson(a, b);  // the one definition (throws on different sizes)
}

// Kinematic transport of a log PSD from its reference speed to ratio x that speed: the local
// mean over +-h bins (the transfer path: housing resonances stay at their frequency) is kept,
// the lines above it (level - local mean) move with the speed. Like the simulated spectra, the
// result is the expectation over the nominal speed's uncertainty (power mean over `scales`),
// so a training case (ratio 1) and a prediction see the same kind of input.
std::vector<double> transport_log_psd(const std::vector<double>& ref, const std::vector<double>& c, double ratio,
                                      const std::vector<double>& scales, int h) {
  const auto lm = local_mean(ref, h);
  std::vector<double> lines(ref.size()), acc(ref.size(), 0.0);
  for (size_t k = 0; k < ref.size(); ++k) lines[k] = std::pow(10.0, ref[k] - lm[k]);
  for (double sc : scales) {
    const auto mv = move_with_speed(lines, c, ratio * sc);
    for (size_t k = 0; k < acc.size(); ++k) acc[k] += mv[k] / static_cast<double>(scales.size());
  }
  std::vector<double> out(ref.size());
  for (size_t k = 0; k < out.size(); ++k) out[k] = lm[k] + std::log10(std::max(acc[k], 1e-300));
  return out;
}

// Envelope (power domain): its content is speed-locked lines over a floor; all of it moves.
std::vector<double> transport_env(const std::vector<double>& ref, const std::vector<double>& c, double ratio,
                                  const std::vector<double>& scales) {
  std::vector<double> acc(ref.size(), 0.0);
  for (double sc : scales) {
    const auto mv = move_with_speed(ref, c, ratio * sc);
    for (size_t k = 0; k < acc.size(); ++k) acc[k] += mv[k] / static_cast<double>(scales.size());
  }
  return acc;
}


std::vector<double> centres(const Grid& g) {
  std::vector<double> c(g.bins());
  for (size_t i = 0; i < c.size(); ++i) c[i] = g.centre_hz(i);
  return c;
}

}  // namespace amb::host::hybrid
