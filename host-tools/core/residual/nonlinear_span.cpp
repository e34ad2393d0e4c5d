#include "host-tools/core/residual/nonlinear_span.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fftw3.h>

namespace amb::host::residual {

std::vector<NonlinearSpan> detect_nonlinear_spans(const std::vector<double>& cur, const std::vector<std::vector<double>>& acc,
                                                  double fs, double bias, const NonlinearOptions& o) {
  std::vector<NonlinearSpan> out;
  const int seg = std::max(16, static_cast<int>(o.block_s * fs));
  const int hop = seg / 2, nb = seg / 2 + 1;
  const size_t n = cur.size();
  if (n < static_cast<size_t>(seg) || acc.empty()) return out;
  std::vector<double> win(static_cast<size_t>(seg)), in(static_cast<size_t>(seg));
  for (int i = 0; i < seg; ++i) win[static_cast<size_t>(i)] = 0.5 - 0.5 * std::cos(2.0 * M_PI * i / seg);
  std::vector<fftw_complex> spec(static_cast<size_t>(nb));
  fftw_plan plan = fftw_plan_dft_r2c_1d(seg, in.data(), spec.data(), FFTW_ESTIMATE);
  std::vector<size_t> starts;
  for (size_t s = 0; s + static_cast<size_t>(seg) <= n; s += static_cast<size_t>(hop)) starts.push_back(s);
  std::vector<std::vector<double>> e(acc.size(), std::vector<double>(starts.size(), 0.0));
  for (size_t c = 0; c < acc.size(); ++c)
    for (size_t b = 0; b < starts.size(); ++b) {
      for (int i = 0; i < seg; ++i) in[static_cast<size_t>(i)] = acc[c][starts[b] + static_cast<size_t>(i)] * win[static_cast<size_t>(i)];
      fftw_execute(plan);
      for (int k = 0; k < nb; ++k) {
        const double f = k * fs / seg;
        if (f >= o.band_lo_hz && f <= o.band_hi_hz)
          e[c][b] += spec[static_cast<size_t>(k)][0] * spec[static_cast<size_t>(k)][0] + spec[static_cast<size_t>(k)][1] * spec[static_cast<size_t>(k)][1];
      }
    }
  fftw_destroy_plan(plan);
  std::vector<double> ratio_db(starts.size(), 0.0), ipk(starts.size(), 0.0);
  for (size_t c = 0; c < acc.size(); ++c) {
    std::vector<double> sorted = e[c];
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
    const double med = std::max(sorted[sorted.size() / 2], 1e-300);
    for (size_t b = 0; b < starts.size(); ++b) ratio_db[b] += 10.0 * std::log10(std::max(e[c][b], 1e-300) / med) / static_cast<double>(acc.size());
  }
  for (size_t b = 0; b < starts.size(); ++b)
    for (int i = 0; i < seg; ++i) ipk[b] = std::max(ipk[b], std::abs(cur[starts[b] + static_cast<size_t>(i)]));
  const double t_end = static_cast<double>(n) / fs;
  for (size_t b = 0; b < starts.size();) {
    auto flagged = [&](size_t k) { return ratio_db[k] > o.min_ratio_db || (bias > 0.0 && ipk[k] > o.current_fraction * bias); };
    if (!flagged(b)) { ++b; continue; }
    size_t k = b;
    double rmax = -1e9, imax = 0.0;
    while (k < starts.size() && flagged(k)) { rmax = std::max(rmax, ratio_db[k]); imax = std::max(imax, ipk[k]); ++k; }
    NonlinearSpan s;
    s.t0_s = std::max(0.0, static_cast<double>(starts[b]) / fs - o.guard_s);
    s.t1_s = std::min(t_end, static_cast<double>(starts[k - 1] + static_cast<size_t>(seg)) / fs + o.guard_s);
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "broadband %.0f-%.0f Hz acceleration up to %.1f dB over its median (mean over channels; rub / contact spikes) "
                  "and control current up to %.2f A (bias %.2f A: %s)",
                  o.band_lo_hz, o.band_hi_hz, rmax, imax, bias, bias > 0.0 && imax > o.current_fraction * bias ? "near saturation" : "below the limit");
    s.reason = buf;
    if (!out.empty() && s.t0_s <= out.back().t1_s) {
      out.back().t1_s = s.t1_s;
      out.back().reason += "; " + s.reason;
    } else {
      out.push_back(s);
    }
    b = k;
  }
  return out;
}

}  // namespace amb::host::residual
