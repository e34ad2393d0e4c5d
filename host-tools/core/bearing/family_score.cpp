#include "host-tools/core/bearing/family_score.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host-tools/core/bearing/line_family.hpp"

namespace amb::host::bearing {
namespace {

// log p of the largest of n Rayleigh bins being above r x median: 1 - (1 - 2^(-r^2))^n.
double log_line_p(double ratio, double n_bins) {
  const double q = std::exp2(-ratio * ratio);
  if (q >= 1.0) return 0.0;
  const double p = -std::expm1(n_bins * std::log1p(-q));
  return std::log(std::max(p, 1e-300));
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<size_t>(std::min<double>(static_cast<double>(v.size()) - 1,
                                                      std::floor(q * static_cast<double>(v.size()))));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

}  // namespace

NormalisedSpectrum normalise_spectrum(const EnvelopeSpectrum& s, double f_max_hz, double floor_halfwidth_hz,
                                      double shaft_hz, int exclude_bins) {
  if (!(floor_halfwidth_hz > 0) || exclude_bins < 0) throw std::invalid_argument("invalid normalisation options");
  NormalisedSpectrum out;
  out.df_hz = s.df_hz;
  if (!(s.df_hz > 0) || s.amplitude.size() < 16) return out;
  const auto n = static_cast<long>(std::min<double>(static_cast<double>(s.amplitude.size()),
                                                    std::ceil(f_max_hz / s.df_hz) + 1));
  const auto total = static_cast<long>(s.amplitude.size());
  const long fw = std::max(8L, std::lround(floor_halfwidth_hz / s.df_hz));
  out.ratio.assign(static_cast<size_t>(n), 0.0);
  out.excluded.assign(static_cast<size_t>(n), 0);
  std::vector<double> win;
  win.reserve(static_cast<size_t>(2 * fw + 1));
  // The median moves slowly: evaluate it every `step` bins.
  const long step = std::max(1L, fw / 8);
  double med = 0.0;
  for (long k = 1; k < n; ++k) {
    if ((k - 1) % step == 0) {
      win.clear();
      for (long j = std::max(1L, k - fw); j <= std::min(total - 1, k + fw); ++j)
        if (std::abs(j - k) > 3) win.push_back(s.amplitude[static_cast<size_t>(j)]);
      auto mid = win.begin() + static_cast<long>(win.size() / 2);
      std::nth_element(win.begin(), mid, win.end());
      med = *mid;
    }
    out.ratio[static_cast<size_t>(k)] = med > 0 ? s.amplitude[static_cast<size_t>(k)] / med : 0.0;
  }
  out.excluded[0] = 1;
  if (shaft_hz > 0) {
    for (int h = 1; h * shaft_hz < static_cast<double>(n) * s.df_hz; ++h) {
      const long c = std::lround(h * shaft_hz / s.df_hz);
      for (long j = c - exclude_bins; j <= c + exclude_bins; ++j)
        if (j >= 0 && j < n) out.excluded[static_cast<size_t>(j)] = 1;
    }
  }
  return out;
}

TemplateScore score_template(const NormalisedSpectrum& s, double base_hz, const std::vector<TemplateLine>& lines,
                             double tolerance, double line_p) {
  TemplateScore t;
  t.lines.resize(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) t.lines[i].label = lines[i].label;
  const auto n = static_cast<long>(s.ratio.size());
  const double df = s.df_hz;
  if (!(df > 0) || n < 16 || !(base_hz > 0) || lines.empty() || !(tolerance > 0)) return t;
  double m_max = 0.0;
  for (const auto& l : lines) m_max = std::max(m_max, l.multiple);
  // Delta grid: the highest line moves by at most one bin per step.
  const double step = df / (m_max * base_hz);
  const long n_steps = std::max(0L, std::lround(tolerance / step));
  double best = 1.0;  // log p of the best delta (<= 0); 1 marks "none yet"
  std::vector<LineScore> cur(lines.size());
  for (long d = -n_steps; d <= n_steps; ++d) {
    const double delta = static_cast<double>(d) * step;
    double x = 0.0;
    int m = 0;
    for (size_t i = 0; i < lines.size(); ++i) {
      const auto& l = lines[i];
      LineScore& r = cur[i];
      r = LineScore{l.label};
      const long c = std::lround((l.multiple * base_hz * (1.0 + delta) + l.offset_hz) / df);
      long b = -1, searched = 0;
      for (long k = c - l.jitter_bins; k <= c + l.jitter_bins; ++k) {
        if (k < 1 || k >= n || s.excluded[static_cast<size_t>(k)]) continue;
        ++searched;
        if (b < 0 || s.ratio[static_cast<size_t>(k)] > s.ratio[static_cast<size_t>(b)]) b = k;
      }
      if (b < 0) continue;  // every bin on a shaft harmonic or outside: no evidence either way
      r.hz = static_cast<double>(b) * df;
      r.ratio = s.ratio[static_cast<size_t>(b)];
      const double lp = log_line_p(r.ratio, static_cast<double>(searched));
      r.p_value = std::exp(lp);
      x += -2.0 * lp;
      ++m;
    }
    const double log_p = m > 0 ? log_chi2_sf_even(x, m) : 0.0;
    if (best > 0.5 || log_p < best) {
      best = log_p;
      t.delta = delta;
      t.lines = cur;
    }
  }
  t.score = best > 0.5 ? 0.0 : -best / std::log(10.0);
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i].fundamental && t.lines[i].p_value < line_p) t.fundamental_present = true;
  return t;
}

double NullFit::log10_p(double score) const {
  if (!(scale > 0)) return 0.0;
  return std::min(0.0, std::log10(0.5) - (score - median) / (scale * std::log(10.0)));
}

double NullFit::score_at(double log10_p_threshold) const {
  return median + scale * std::log(10.0) * (std::log10(0.5) - log10_p_threshold);
}

NullFit fit_null(std::vector<double> draws) {
  NullFit f;
  f.samples = static_cast<int>(draws.size());
  if (draws.size() < 8) return f;
  f.median = quantile(draws, 0.5);
  f.q90 = quantile(draws, 0.9);
  f.q99 = quantile(draws, 0.99);
  const double top = *std::max_element(draws.begin(), draws.end());
  f.scale = std::max({(f.q90 - f.median) / std::log(5.0), (f.q99 - f.median) / std::log(50.0),
                      (top - f.median) / std::log(0.5 * static_cast<double>(draws.size())), 1.0 / std::log(10.0)});
  return f;
}

std::vector<double> surrogate_scores(const NormalisedSpectrum& s, double base_hz, const std::vector<TemplateLine>& lines,
                                     double tolerance, const std::vector<double>& forbidden_hz, bool every_line) {
  std::vector<double> scores;
  auto hits_forbidden = [&](double pseudo_base) {
    for (const auto& l : lines) {
      if (!l.fundamental && !every_line) continue;
      const double pos = l.multiple * pseudo_base + l.offset_hz;
      for (double q : forbidden_hz)
        if (std::abs(pos - q) < tolerance * std::max(pos, q) + 2.0 * s.df_hz) return true;
    }
    return false;
  };
  for (const auto& [lo, hi] : {std::pair{0.55, 0.95}, std::pair{1.05, 1.8}}) {
    for (double u = lo; u <= hi + 1e-9; u += 0.5 * tolerance) {
      const double b = u * base_hz;
      if (hits_forbidden(b)) continue;
      scores.push_back(score_template(s, b, lines, tolerance, 1.0).score);
    }
  }
  return scores;
}

}  // namespace amb::host::bearing
