#include "host-tools/core/residual/modal_peaks.hpp"

#include <algorithm>
#include <cmath>

namespace amb::host::residual {

std::vector<MeasuredPeak> find_peaks(const std::vector<double>& f, const std::vector<std::vector<std::complex<double>>>& h,
                                     const std::vector<std::vector<double>>& coh, const PeakOptions& o) {
  std::vector<MeasuredPeak> out;
  const size_t nch = h.size(), nb = f.size();
  if (nch == 0 || nb < 5) return out;
  std::vector<bool> ok(nb, false);
  for (size_t i = 0; i < nb; ++i) {
    if (f[i] < o.f_min_hz || f[i] > o.f_max_hz) continue;
    size_t good = 0;
    for (size_t c = 0; c < nch; ++c) good += coh[c][i] >= o.min_coherence ? 1 : 0;
    ok[i] = 2 * good >= nch;
  }
  std::vector<double> norm(nch, 0.0);
  for (size_t c = 0; c < nch; ++c) {
    int n = 0;
    for (size_t i = 0; i < nb; ++i)
      if (ok[i]) { norm[c] += std::norm(h[c][i]); ++n; }
    norm[c] = n > 0 && norm[c] > 0.0 ? norm[c] / n : 1.0;
  }
  std::vector<double> s(nb, 0.0);
  for (size_t i = 0; i < nb; ++i)
    for (size_t c = 0; c < nch; ++c) s[i] += std::norm(h[c][i]) / norm[c];
  const double df = f[1] - f[0];
  for (size_t i = 1; i + 1 < nb; ++i) {
    if (!ok[i]) continue;
    const double half = std::max(0.02 * f[i], 1.0);
    bool is_max = true;
    std::vector<double> around;
    for (size_t j = 0; j < nb; ++j) {
      if (std::abs(f[j] - f[i]) <= half && j != i && s[j] > s[i]) { is_max = false; break; }
      if (std::abs(f[j] - f[i]) <= 0.15 * f[i]) around.push_back(s[j]);
    }
    if (!is_max || around.empty()) continue;
    std::nth_element(around.begin(), around.begin() + static_cast<long>(around.size() / 2), around.end());
    const double med = around[around.size() / 2];
    if (!(med > 0.0) || s[i] / med < o.min_prominence) continue;
    MeasuredPeak p;
    const double a = std::log(s[i - 1]), b = std::log(s[i]), c = std::log(s[i + 1]);
    const double den = a - 2.0 * b + c;
    p.frequency_hz = f[i] + (den < 0.0 ? std::clamp(0.5 * (a - c) / den, -0.5, 0.5) : 0.0) * df;
    p.prominence = s[i] / med;
    for (size_t ch = 0; ch < nch; ++ch) p.shape.push_back(h[ch][i]);
    out.push_back(p);
  }
  return out;
}

double mac(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b) {
  std::complex<double> ab(0.0, 0.0);
  double aa = 0.0, bb = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    ab += std::conj(a[i]) * b[i];
    aa += std::norm(a[i]);
    bb += std::norm(b[i]);
  }
  return aa > 0.0 && bb > 0.0 ? std::norm(ab) / (aa * bb) : 0.0;
}

}  // namespace amb::host::residual
