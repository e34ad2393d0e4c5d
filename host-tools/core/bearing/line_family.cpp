#include "host-tools/core/bearing/line_family.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace amb::host::bearing {

double log_chi2_sf_even(double x, int m) {
  if (m <= 0) return 0.0;
  if (!(x > 0)) return 0.0;
  // Q = exp(-x/2) sum_{k<m} (x/2)^k / k!, summed in logs (log-sum-exp).
  const double h = 0.5 * x;
  std::vector<double> terms(static_cast<size_t>(m));
  double term = 0.0;  // log of (x/2)^k / k!
  double top = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < m; ++k) {
    if (k > 0) term += std::log(h) - std::log(static_cast<double>(k));
    terms[static_cast<size_t>(k)] = term;
    top = std::max(top, term);
  }
  double sum = 0.0;
  for (double t : terms) sum += std::exp(t - top);
  return std::min(0.0, -h + top + std::log(sum));
}

namespace {

double median_of(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// log p of a line: largest of n Rayleigh bins above r * median.
double log_line_p(double ratio, double n_bins) {
  const double q = std::exp2(-ratio * ratio);  // per-bin exceedance
  if (q >= 1.0) return 0.0;
  // 1 - (1-q)^n computed stably.
  const double p = -std::expm1(n_bins * std::log1p(-q));
  return std::log(std::max(p, 1e-300));
}

struct Prepared {
  double centre_hz = 0.0;    // nominal position (delta = 0)
  long jitter_bins = 1;      // search +- bins around the delta-moved position
  double median = 0.0;       // floor
};

}  // namespace

FamilyTest test_family(const EnvelopeSpectrum& s, double base_hz, const std::vector<FamilyLine>& lines,
                       const FamilyTestOptions& o) {
  FamilyTest t;
  t.base_hz = base_hz;
  t.lines.resize(lines.size());
  const double df = s.df_hz;
  const auto n = static_cast<long>(s.amplitude.size());
  if (df <= 0 || n < 16 || !(base_hz > 0) || lines.empty()) return t;
  double m_max = 0.0;
  for (const auto& l : lines) m_max = std::max(m_max, l.multiple);
  // Floors: one per line, from the bins around its nominal position, its whole search range excluded.
  std::vector<Prepared> prep(lines.size());
  std::vector<double> floor_bins;
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto& l = lines[i];
    Prepared& p = prep[i];
    p.centre_hz = l.multiple * base_hz + l.offset_hz;
    p.jitter_bins = 1 + std::lround(l.offset_uncertainty * std::abs(l.offset_hz) / df);
    const double half_hz = o.tolerance * l.multiple * base_hz + static_cast<double>(p.jitter_bins) * df;
    const double fh = o.floor_halfwidth_hz > 0 ? o.floor_halfwidth_hz : std::max(10.0 * half_hz, 5.0);
    const long c = std::lround(p.centre_hz / df);
    const long w = std::lround(half_hz / df);
    const long fw = std::lround(fh / df);
    floor_bins.clear();
    for (long k = std::max(1L, c - fw); k <= std::min(n - 1, c + fw); ++k)
      if (k < c - w || k > c + w) floor_bins.push_back(s.amplitude[static_cast<size_t>(k)]);
    p.median = floor_bins.size() >= 8 ? median_of(floor_bins) : 0.0;
  }
  // Delta grid: the highest line moves by at most one bin per step.
  const double step = df / (m_max * base_hz);
  const long n_steps = std::max(0L, std::lround(o.tolerance / step));
  t.trials = std::max(1.0, 2.0 * o.tolerance * base_hz / df);
  double best_log_p = 0.0;
  double best_delta = 0.0;
  bool first = true;
  std::vector<FamilyLineResult> cur(lines.size());
  for (long d = -n_steps; d <= n_steps; ++d) {
    const double delta = static_cast<double>(d) * step;
    double x = 0.0;
    int m = 0;
    for (size_t i = 0; i < lines.size(); ++i) {
      const auto& l = lines[i];
      FamilyLineResult& r = cur[i];
      r = FamilyLineResult{};
      r.ambiguous = l.ambiguous;
      const double pos = l.multiple * base_hz * (1.0 + delta) + l.offset_hz;
      const long c = std::lround(pos / df);
      const long j = prep[i].jitter_bins;
      if (c - j < 1 || c + j >= n || !(prep[i].median > 0)) continue;
      long b = c - j;
      for (long k = c - j; k <= c + j; ++k)
        if (s.amplitude[static_cast<size_t>(k)] > s.amplitude[static_cast<size_t>(b)]) b = k;
      r.hz = static_cast<double>(b) * df;
      r.ratio = s.amplitude[static_cast<size_t>(b)] / prep[i].median;
      const double lp = log_line_p(r.ratio, static_cast<double>(2 * j + 1));
      r.p_value = std::exp(lp);
      if (!r.ambiguous && o.shaft_hz > 0) {
        const double k = std::round(pos / o.shaft_hz);
        if (k >= 1 && k <= 64 &&
            std::abs(pos - k * o.shaft_hz) <= static_cast<double>(j + 1) * df + o.shaft_tolerance * k * o.shaft_hz)
          r.ambiguous = true;
      }
      if (r.ambiguous) continue;
      x += -2.0 * lp;
      ++m;
    }
    const double log_p = m > 0 ? log_chi2_sf_even(x, m) : 0.0;
    if (first || log_p < best_log_p) {
      first = false;
      best_log_p = log_p;
      best_delta = delta;
      t.lines = cur;
    }
  }
  t.delta = best_delta;
  t.log10_p = std::min(0.0, best_log_p / std::log(10.0) + std::log10(t.trials));
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto& r = t.lines[i];
    if (r.ambiguous || !(r.p_value < o.line_p)) continue;
    ++t.lines_present;
    if (lines[i].fundamental) t.fundamental_present = true;
  }
  return t;
}

}  // namespace amb::host::bearing
