#include "firmware/sweep/multisine.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "firmware/sweep/sweep_params.hpp"

namespace amb::fw {

std::vector<uint32_t> multisine_bins(double rate_hz, uint32_t n, double f_min_hz, double f_max_hz, uint32_t lines) {
  std::vector<uint32_t> bins;
  if (n < 4 || !(rate_hz > 0.0) || lines == 0) return bins;
  const BinRange r = sweep_bin_range(rate_hz, n, f_min_hz, f_max_hz);
  const uint32_t k_lo = r.lo, k_hi = r.hi;
  if (k_hi < k_lo) return bins;
  if (lines == 1 || k_hi == k_lo) {
    bins.push_back(k_lo);
    return bins;
  }
  for (uint32_t l = 0; l < lines; ++l) {
    const double x = static_cast<double>(l) / static_cast<double>(lines - 1);
    const auto k = static_cast<uint32_t>(std::lround(static_cast<double>(k_lo) * std::pow(static_cast<double>(k_hi) / k_lo, x)));
    if (bins.empty() || k > bins.back()) bins.push_back(k);
  }
  return bins;
}

namespace {

// One period from the phases: x[n] = sum_l cos(2 pi k_l n / N + phi_l), by table lookup.
void synthesise(const std::vector<uint32_t>& bins, const std::vector<double>& phases, const std::vector<double>& c,
                const std::vector<double>& sn, std::vector<double>& x) {
  const size_t n = c.size();
  std::fill(x.begin(), x.end(), 0.0);
  for (size_t l = 0; l < bins.size(); ++l) {
    const double cp = std::cos(phases[l]), sp = std::sin(phases[l]);
    size_t m = 0;
    for (size_t i = 0; i < n; ++i) {
      x[i] += cp * c[m] - sp * sn[m];
      m += bins[l];
      if (m >= n) m -= n;
    }
  }
}

double crest_of(const std::vector<double>& x) {
  double peak = 0.0, sq = 0.0;
  for (double v : x) {
    peak = std::max(peak, std::abs(v));
    sq += v * v;
  }
  const double rms = std::sqrt(sq / static_cast<double>(x.size()));
  return rms > 0.0 ? peak / rms : 0.0;
}

}  // namespace

std::string design_multisine(double rate_hz, uint32_t n, double f_min_hz, double f_max_hz, uint32_t lines,
                             MultisineDesign& out) {
  if (n < 4) return "samples_per_period must be at least 4";
  MultisineDesign d;
  d.bins = multisine_bins(rate_hz, n, f_min_hz, f_max_hz, lines);
  if (d.bins.empty()) return "the band holds no bin of the period (widen it or lengthen the period)";
  const size_t count = d.bins.size();
  // Start from Schroeder's phases, then lower the crest factor by clipping: clip the period at
  // a fraction of its peak, keep the clipped signal's phases at the lines (amplitudes stay
  // equal, nothing leaks to other bins), repeat; the lowest crest factor seen is kept.
  d.phases_rad.resize(count);
  for (size_t l = 0; l < count; ++l) {
    const double i = static_cast<double>(l + 1);
    d.phases_rad[l] = -std::numbers::pi * i * (i - 1.0) / static_cast<double>(count);
  }
  std::vector<double> c(n), sn(n), x(n);
  for (uint32_t m = 0; m < n; ++m) {
    c[m] = std::cos(2.0 * std::numbers::pi * m / n);
    sn[m] = std::sin(2.0 * std::numbers::pi * m / n);
  }
  synthesise(d.bins, d.phases_rad, c, sn, x);
  double best = crest_of(x);
  std::vector<double> phases = d.phases_rad;
  for (int it = 0; it < 150 && count > 1; ++it) {
    double peak = 0.0;
    for (double v : x) peak = std::max(peak, std::abs(v));
    const double clip = 0.8 * peak;
    for (double& v : x) v = std::clamp(v, -clip, clip);
    for (size_t l = 0; l < count; ++l) {
      double re = 0.0, im = 0.0;
      size_t m = 0;
      for (uint32_t i = 0; i < n; ++i) {
        re += x[i] * c[m];
        im -= x[i] * sn[m];
        m += d.bins[l];
        if (m >= n) m -= n;
      }
      phases[l] = std::atan2(im, re);
    }
    synthesise(d.bins, phases, c, sn, x);
    const double cf = crest_of(x);
    if (cf < best) {
      best = cf;
      d.phases_rad = phases;
    }
  }
  synthesise(d.bins, d.phases_rad, c, sn, x);
  double peak = 0.0;
  for (double v : x) peak = std::max(peak, std::abs(v));
  d.crest_factor = crest_of(x);
  d.table.resize(n);
  for (uint32_t k = 0; k < n; ++k) d.table[k] = static_cast<float>(x[k] / peak);
  out = std::move(d);
  return "";
}

}  // namespace amb::fw
