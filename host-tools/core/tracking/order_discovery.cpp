#include "host-tools/core/tracking/order_discovery.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "host-tools/core/bearing/line_family.hpp"
#include "model/signal/spectral_floor.hpp"

namespace amb::host {
namespace {

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const { fftw_destroy_plan(p); }
};

// Chi-squared (2K dof) survival at 2K * t (t relative to the mean).
double sf(double t, int k) { return std::exp(bearing::log_chi2_sf_even(2.0 * k * t, k)); }

// t with sf(t) = p, by bisection (sf decreasing in t).
double inverse_sf(double p, int k) {
  double lo = 0.0, hi = 1.0;
  while (sf(hi, k) > p) hi *= 2.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (sf(mid, k) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// a/b near p/q (p, q <= 4) within rel: the same line family (or the same broad line).
bool simple_ratio(double a, double b, double rel) {
  const double r = a / b;
  for (int p = 1; p <= 4; ++p)
    for (int q = 1; q <= 4; ++q)
      if (std::abs(r - static_cast<double>(p) / q) < rel * r) return true;
  return false;
}

}  // namespace

OrderDiscovery discover_orders(const std::vector<double>& x, double fs_hz, const OrderDiscoveryOptions& o,
                               double max_window_s) {
  if (!(fs_hz > 0)) throw std::invalid_argument("order discovery: fs must be > 0 Hz");
  if (!(o.min_speed_hz > 0 && o.max_speed_hz > o.min_speed_hz) || o.max_order < 1 || o.max_order > 8)
    throw std::invalid_argument("order discovery: invalid speed range or max_order");
  const double rec_s = static_cast<double>(x.size()) / fs_hz;
  OrderDiscovery d;
  d.segment_s = std::min(o.segment_s, rec_s / 3.0);
  const auto n_seg = static_cast<size_t>(std::lround(d.segment_s * fs_hz));
  if (n_seg < 64) throw std::invalid_argument("order discovery: record too short");
  size_t nfft = 1;
  while (nfft < 2 * n_seg) nfft *= 2;
  std::vector<double> in(nfft, 0.0), power(nfft / 2 + 1, 0.0);
  std::vector<std::complex<double>> out(nfft / 2 + 1);
  std::unique_ptr<fftw_plan_s, PlanDeleter> plan(fftw_plan_dft_r2c_1d(
      static_cast<int>(nfft), in.data(), reinterpret_cast<fftw_complex*>(out.data()), FFTW_ESTIMATE));
  int k_seg = 0;
  // Per-segment spectra up to just above the highest 1x, for the coarse track.
  const auto n_keep = std::min(out.size(), static_cast<size_t>(std::ceil(1.2 * o.max_speed_hz / (fs_hz / static_cast<double>(nfft)))) + 8);
  std::vector<std::vector<double>> seg_power;
  std::vector<double> seg_t;
  for (size_t start = 0; start + n_seg <= x.size(); start += n_seg / 2) {
    double mean = 0.0;
    for (size_t i = 0; i < n_seg; ++i) mean += x[start + i];
    mean /= static_cast<double>(n_seg);
    std::fill(in.begin(), in.end(), 0.0);
    for (size_t i = 0; i < n_seg; ++i)
      in[i] = (x[start + i] - mean) * (0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n_seg)));
    fftw_execute(plan.get());
    for (size_t k = 0; k < power.size(); ++k) power[k] += std::norm(out[k]);
    seg_power.emplace_back(n_keep);
    for (size_t k = 0; k < n_keep; ++k) seg_power.back()[k] = std::norm(out[k]);
    seg_t.push_back((static_cast<double>(start) + 0.5 * static_cast<double>(n_seg)) / fs_hz);
    ++k_seg;
  }
  d.bin_hz = fs_hz / static_cast<double>(nfft);
  // Floor and prominence.
  const size_t n = power.size();
  std::vector<double> level(n), floor_db(n), prom(n);
  for (size_t k = 0; k < n; ++k) level[k] = 10.0 * std::log10(power[k] / k_seg + 1e-300);
  const size_t block = 64;
  std::vector<double> scratch(block), medians((n + block - 1) / block);
  model::signal::block_median_floor(level, block, scratch, medians, floor_db);
  for (size_t k = 0; k < n; ++k) prom[k] = level[k] - floor_db[k];
  // Presence threshold: 50 % overlapping Hann segments are nearly independent (K_eff ~ 0.9 K);
  // zero padding x2 doubles the bins, not the independent ones.
  const int k_eff = std::max(1, static_cast<int>(std::floor(0.9 * k_seg)));
  const double f_top = std::min(0.45 * fs_hz, o.max_order * o.max_speed_hz * (1.0 + o.line_tolerance));
  const double n_searched = std::max(1.0, f_top / d.bin_hz / 2.0);
  d.threshold_db = 10.0 * std::log10(inverse_sf(o.false_alarm / n_searched, k_eff) / inverse_sf(0.5, k_eff));

  // Prominence of the strongest bin within the tolerance of f, if that bin is a line: the
  // largest bin within +-3 resolution widths (3 / segment_s Hz), so a window sidelobe of a
  // stronger neighbour is not taken for a line of its own.
  const auto guard = static_cast<size_t>(std::ceil(3.0 / d.segment_s / d.bin_hz));
  auto peak = [&](double f) -> size_t {
    const double half = d.bin_hz + o.line_tolerance * f;
    const auto b0 = static_cast<size_t>(std::max(1.0, std::floor((f - half) / d.bin_hz)));
    const auto b1 = std::min(n - 2, static_cast<size_t>(std::ceil((f + half) / d.bin_hz)));
    if (b0 > b1) return 0;
    size_t b = b0;
    for (size_t i = b0; i <= b1; ++i)
      if (level[i] > level[b]) b = i;
    for (size_t i = b > guard ? b - guard : 1; i <= std::min(n - 1, b + guard); ++i)
      if (level[i] > level[b]) return 0;
    return b;
  };
  auto line = [&](double f) {
    const size_t b = peak(f);
    return b == 0 ? -1e9 : prom[b];
  };
  auto score = [&](double f, std::vector<double>* orders, std::vector<double>* proms) {
    if (line(f) < d.threshold_db) return -1.0;
    double s = 0.0;
    int missing = 0;
    for (int k = 1; k <= o.max_order && k * f < 0.45 * fs_hz; ++k) {
      const double p = line(k * f);
      // A shaft's harmonics form a comb from 1x up: the comb ends at two missing orders in a row
      // (an isolated line at 7x is something else's line).
      missing = p >= d.threshold_db ? 0 : missing + 1;
      if (missing >= 2) break;
      if (p >= d.threshold_db) {
        s += p - d.threshold_db;
        if (orders) orders->push_back(k);
        if (proms) proms->push_back(p);
      }
      const double ph = line((k - 0.5) * f);
      if (k > 1 || 0.5 * f >= o.min_speed_hz * 0.5) {
        if (ph >= d.threshold_db) s -= ph - d.threshold_db;
      }
    }
    return s;
  };
  const double step = 0.5 * d.bin_hz;
  std::vector<std::pair<double, double>> cands;  // f, score
  for (double f = o.min_speed_hz; f <= o.max_speed_hz; f += step) {
    const double s = score(f, nullptr, nullptr);
    if (s > 0) cands.emplace_back(f, s);
  }
  if (cands.empty()) {
    d.reason = "no line in the speed range stands above the noise at the stated false-alarm rate";
    return d;
  }
  const auto best = *std::max_element(cands.begin(), cands.end(),
                                      [](const auto& a, const auto& b) { return a.second < b.second; });
  d.found = true;
  {  // speed: the 1x peak, parabolic interpolation of the log level
    const size_t b = peak(best.first);
    const double a = level[b - 1], c = level[b], e = level[b + 1];
    const double den = a - 2.0 * c + e;
    const double shift = den < 0 ? std::clamp(0.5 * (a - e) / den, -0.5, 0.5) : 0.0;
    d.speed_hz = (static_cast<double>(b) + shift) * d.bin_hz;
  }
  d.score = best.second;
  score(best.first, &d.orders, &d.prominence_db);
  for (const auto& [f, s] : cands)
    if (!simple_ratio(f, d.speed_hz, 0.03 + 2.0 * o.line_tolerance + 4.0 * d.bin_hz / d.speed_hz) &&
        s > d.runner_up_score) {
      d.runner_up_score = s;
      d.runner_up_hz = f;
    }
  d.ambiguous = d.runner_up_score > 0.0 && d.runner_up_score >= o.ambiguity_ratio * d.score;
  // Coarse track: each segment's own 1x peak within the drift the acceleration limit allows over
  // the record (at least 1 %), kept if it is the largest bin within 3 resolution widths and
  // stands above the one-segment presence threshold over the segment's median in that range.
  {
    const double half = std::max(0.01 * d.speed_hz, o.max_accel_hz_per_s * rec_s) + 3.0 / d.segment_s;
    const double thr1 = inverse_sf(o.false_alarm, 1) / inverse_sf(0.5, 1);
    for (size_t sgi = 0; sgi < seg_power.size(); ++sgi) {
      const auto& sp = seg_power[sgi];
      const auto b0 = static_cast<size_t>(std::max(1.0, std::floor((d.speed_hz - half) / d.bin_hz)));
      const auto b1 = std::min(sp.size() - 2, static_cast<size_t>(std::ceil((d.speed_hz + half) / d.bin_hz)));
      if (b0 + 4 > b1) continue;
      size_t b = b0;
      for (size_t i = b0; i <= b1; ++i)
        if (sp[i] > sp[b]) b = i;
      std::vector<double> v(sp.begin() + static_cast<std::ptrdiff_t>(b0), sp.begin() + static_cast<std::ptrdiff_t>(b1 + 1));
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      const double med = v[v.size() / 2];
      if (!(med > 0) || sp[b] < thr1 * med || b == b0 || b == b1) continue;
      const double la = std::log(sp[b - 1] + 1e-300), lc = std::log(sp[b]), le = std::log(sp[b + 1] + 1e-300);
      const double den = la - 2.0 * lc + le;
      const double shift = den < 0 ? std::clamp(0.5 * (la - le) / den, -0.5, 0.5) : 0.0;
      d.coarse_t_s.push_back(seg_t[sgi]);
      d.coarse_hz.push_back((static_cast<double>(b) + shift) * d.bin_hz);
    }
  }
  // Window from the line SNR: a stationary line's prominence grows as 10 log10(T).
  const double p_max = *std::max_element(d.prominence_db.begin(), d.prominence_db.end());
  const double t = d.segment_s * std::pow(10.0, (o.target_prominence_db - p_max) / 10.0);
  // ... and long enough to resolve the 1x: the tracker's stated minimum speed is two Hamming
  // main-lobe half-widths, 4 / T; ask for 3x that margin, T >= 12 / f.
  const double t_resolve = 12.0 / d.speed_hz;
  d.window_s = std::clamp(std::ceil(std::max(t, t_resolve) * 10.0) / 10.0, 0.5, std::max(0.5, max_window_s));
  d.resolved = t_resolve <= d.window_s + 1e-9;
  char buf[320];
  if (d.ambiguous)
    std::snprintf(buf, sizeof buf,
                  "two unrelated line families: %.3f Hz (score %.1f dB) and %.3f Hz (score %.1f dB); the record does "
                  "not say which is the shaft (narrow the speed range in the machine profile)",
                  d.speed_hz, d.score, d.runner_up_hz, d.runner_up_score);
  else
    std::snprintf(buf, sizeof buf, "shaft line family at %.3f Hz with %zu orders (strongest %.1f dB, threshold %.1f dB)",
                  d.speed_hz, d.orders.size(), p_max, d.threshold_db);
  d.reason = buf;
  return d;
}

}  // namespace amb::host
