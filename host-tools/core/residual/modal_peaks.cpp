#include "host-tools/core/residual/modal_peaks.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <nlopt.hpp>

namespace amb::host::residual {

namespace {

std::vector<bool> coherent_bins(const std::vector<double>& f, const std::vector<std::vector<double>>& coh, const PeakOptions& o) {
  const size_t nch = coh.size(), nb = f.size();
  std::vector<bool> ok(nb, false);
  for (size_t i = 0; i < nb; ++i) {
    if (f[i] < o.f_min_hz || f[i] > o.f_max_hz) continue;
    size_t good = 0;
    for (size_t c = 0; c < nch; ++c) good += coh[c][i] >= o.min_coherence ? 1 : 0;
    ok[i] = 2 * good >= nch;
  }
  return ok;
}

}  // namespace

std::vector<double> channel_norms(const std::vector<double>& f, const std::vector<std::vector<std::complex<double>>>& h,
                                  const std::vector<std::vector<double>>& coh, const PeakOptions& o) {
  const size_t nch = h.size(), nb = f.size();
  const auto ok = coherent_bins(f, coh, o);
  std::vector<double> norm(nch, 0.0);
  for (size_t c = 0; c < nch; ++c) {
    int n = 0;
    for (size_t i = 0; i < nb; ++i)
      if (ok[i]) { norm[c] += std::norm(h[c][i]); ++n; }
    norm[c] = n > 0 && norm[c] > 0.0 ? norm[c] / n : 1.0;
  }
  return norm;
}

std::vector<MeasuredPeak> find_peaks(const std::vector<double>& f, const std::vector<std::vector<std::complex<double>>>& h,
                                     const std::vector<std::vector<double>>& coh, const PeakOptions& o) {
  std::vector<MeasuredPeak> out;
  const size_t nch = h.size(), nb = f.size();
  if (nch == 0 || nb < 5) return out;
  const auto ok = coherent_bins(f, coh, o);
  const auto norm = channel_norms(f, h, coh, o);
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

namespace {

using cd = std::complex<double>;

struct PoleFitContext {
  std::vector<double> f;                 // bins in the band, Hz
  std::vector<std::vector<cd>> h;        // [channel][bin]
  std::vector<std::vector<double>> w;    // [channel][bin]
  int poles = 0;
  Eigen::MatrixXcd residues;             // (poles + 2) x channels
};

double pole_cost(const std::vector<double>& x, PoleFitContext& c, bool keep) {
  const Eigen::Index nb = static_cast<Eigen::Index>(c.f.size()), np = c.poles;
  Eigen::MatrixXcd basis(nb, np + 2);
  for (Eigen::Index i = 0; i < nb; ++i) {
    const double w = 2.0 * M_PI * c.f[static_cast<size_t>(i)];
    for (Eigen::Index k = 0; k < np; ++k) {
      const double wk = 2.0 * M_PI * x[static_cast<size_t>(2 * k)], z = x[static_cast<size_t>(2 * k + 1)];
      basis(i, k) = -w * w / cd(wk * wk - w * w, 2.0 * z * wk * w);
    }
    basis(i, np) = -w * w;
    basis(i, np + 1) = 1.0;
  }
  double s = 0.0;
  if (keep) c.residues.resize(np + 2, static_cast<Eigen::Index>(c.h.size()));
  for (size_t ch = 0; ch < c.h.size(); ++ch) {
    Eigen::VectorXcd y(nb);
    Eigen::MatrixXcd bw = basis;
    double norm = 0.0;
    for (Eigen::Index i = 0; i < nb; ++i) {
      const double sw = std::sqrt(c.w[ch][static_cast<size_t>(i)]);
      y(i) = sw * c.h[ch][static_cast<size_t>(i)];
      bw.row(i) *= sw;
      norm += std::norm(y(i));
    }
    if (!(norm > 0.0)) continue;
    const Eigen::VectorXcd r = bw.colPivHouseholderQr().solve(y);
    if (keep) c.residues.col(static_cast<Eigen::Index>(ch)) = r;
    s += (bw * r - y).squaredNorm() / norm;  // each channel counts alike
  }
  return s;
}

double pole_cost_nlopt(unsigned n, const double* x, double*, void* data) {
  auto* c = static_cast<PoleFitContext*>(data);
  const double v = pole_cost(std::vector<double>(x, x + n), *c, false);
  return std::isfinite(v) ? v : 1e30;
}

}  // namespace

std::vector<ModalEstimate> fit_modes(const std::vector<double>& f_hz, const std::vector<std::vector<cd>>& h,
                                     const std::vector<std::vector<double>>& w, double lo, double hi, const std::vector<double>& start_hz) {
  PoleFitContext c;
  c.poles = static_cast<int>(start_hz.size());
  c.h.assign(h.size(), {});
  c.w.assign(h.size(), {});
  for (size_t i = 0; i < f_hz.size(); ++i) {
    if (f_hz[i] < lo || f_hz[i] > hi) continue;
    c.f.push_back(f_hz[i]);
    for (size_t ch = 0; ch < h.size(); ++ch) {
      c.h[ch].push_back(h[ch][i]);
      c.w[ch].push_back(w[ch][i]);
    }
  }
  std::vector<ModalEstimate> out;
  if (c.poles == 0 || c.f.size() < static_cast<size_t>(3 * c.poles + 4)) return out;
  std::vector<double> x, lb, ub;
  for (double f0 : start_hz) {
    x.push_back(f0);
    x.push_back(0.01);
    lb.push_back(lo);
    ub.push_back(hi);
    lb.push_back(1e-4);
    ub.push_back(0.2);
  }
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(x.size()));
  opt.set_lower_bounds(lb);
  opt.set_upper_bounds(ub);
  opt.set_min_objective(pole_cost_nlopt, &c);
  opt.set_maxeval(3000);
  opt.set_xtol_rel(1e-7);
  double fmin = 0.0;
  try {
    opt.optimize(x, fmin);
  } catch (const std::exception&) {
    // roundoff-limited stop: x holds the best point
  }
  pole_cost(x, c, true);
  for (int k = 0; k < c.poles; ++k) {
    ModalEstimate m;
    m.frequency_hz = x[static_cast<size_t>(2 * k)];
    m.damping_ratio = x[static_cast<size_t>(2 * k + 1)];
    for (size_t ch = 0; ch < h.size(); ++ch) m.shape.push_back(c.residues(k, static_cast<Eigen::Index>(ch)));
    out.push_back(m);
  }
  std::sort(out.begin(), out.end(), [](const ModalEstimate& a, const ModalEstimate& b) { return a.frequency_hz < b.frequency_hz; });
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
