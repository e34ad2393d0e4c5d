#include "host-tools/core/sweep/sweep_estimate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <fftw3.h>

#include "host-tools/core/io/number_text.hpp"
#include "model/analysis/closed_loop.hpp"

namespace amb::host::sweep {
namespace {

using cd = std::complex<double>;

double normal_quantile(double p) {
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// DFT of whole periods (no window) with one FFTW plan for the period length.
class PeriodDft {
 public:
  explicit PeriodDft(int n) : n_(n), in_(static_cast<size_t>(n)), out_(static_cast<size_t>(n / 2 + 1)) {
    plan_ = fftw_plan_dft_r2c_1d(n, in_.data(), out_.data(), FFTW_ESTIMATE);
  }
  ~PeriodDft() { fftw_destroy_plan(plan_); }
  PeriodDft(const PeriodDft&) = delete;
  PeriodDft& operator=(const PeriodDft&) = delete;
  // DFT values of x[start .. start + n) at `bins`, into out[i].
  void at(const std::vector<double>& x, size_t start, const std::vector<int>& bins, std::vector<cd>& out) {
    std::copy(x.begin() + static_cast<std::ptrdiff_t>(start), x.begin() + static_cast<std::ptrdiff_t>(start) + n_, in_.begin());
    fftw_execute(plan_);
    out.resize(bins.size());
    for (size_t i = 0; i < bins.size(); ++i) {
      const auto& c = out_[static_cast<size_t>(bins[i])];
      out[i] = cd(c[0], c[1]);
    }
  }

 private:
  int n_;
  std::vector<double> in_;
  std::vector<fftw_complex> out_;
  fftw_plan plan_;
};

void set_band(TransferEstimate& t, double var, int periods, double level) {
  t.sigma = std::sqrt(std::max(0.0, var));
  const double q = student_t_quantile(level, 2.0 * (periods - 1));
  const double half = q * t.sigma / std::sqrt(2.0);
  t.mag_lo = std::max(0.0, std::abs(t.h) - half);
  t.mag_hi = std::abs(t.h) + half;
}

// Reported estimate referenced to r (the injected e): h = sum conj(R) Y / sum conj(R) X.
TransferEstimate referenced(const std::vector<cd>& r, const std::vector<cd>& x, const std::vector<cd>& y, double level) {
  const size_t p = r.size();
  cd ry = 0.0, rx = 0.0;
  for (size_t i = 0; i < p; ++i) {
    ry += std::conj(r[i]) * y[i];
    rx += std::conj(r[i]) * x[i];
  }
  TransferEstimate t = h1_h2({x, y}, level);
  t.h = std::abs(rx) > 0.0 ? ry / rx : cd(0.0, 0.0);
  cd xm = 0.0;
  double rr = 0.0;
  for (size_t i = 0; i < p; ++i) {
    xm += x[i];
    rr += std::norm(y[i] - t.h * x[i]);
  }
  xm /= static_cast<double>(p);
  const double den = static_cast<double>(p) * std::norm(xm);
  set_band(t, den > 0.0 ? rr / static_cast<double>(p - 1) / den : 0.0, static_cast<int>(p), level);
  return t;
}

std::string zone_of(double v) { return model::analysis::to_string(model::analysis::iso14839_zone(v)); }

}  // namespace

double student_t_quantile(double level, double dof) {
  const double z = normal_quantile(0.5 + 0.5 * level);
  const double z2 = z * z, v = std::max(2.0, dof);
  return z + (z2 * z + z) / (4.0 * v) + (5.0 * z2 * z2 * z + 16.0 * z2 * z + 3.0 * z) / (96.0 * v * v) +
         (3.0 * z2 * z2 * z2 * z + 19.0 * z2 * z2 * z + 17.0 * z2 * z - 15.0 * z) / (384.0 * v * v * v);
}

TransferEstimate h1_h2(const PeriodSpectra& s, double band_level) {
  const size_t p = s.x.size();
  if (p < 2 || s.y.size() != p) throw std::invalid_argument("sweep estimate: need at least two periods of x and y");
  cd sxy = 0.0;
  double sxx = 0.0, syy = 0.0;
  for (size_t i = 0; i < p; ++i) {
    sxy += std::conj(s.x[i]) * s.y[i];
    sxx += std::norm(s.x[i]);
    syy += std::norm(s.y[i]);
  }
  TransferEstimate t;
  t.h1 = sxx > 0.0 ? sxy / sxx : cd(0.0, 0.0);
  t.h2 = std::abs(sxy) > 0.0 ? syy / std::conj(sxy) : cd(0.0, 0.0);
  t.coherence = sxx > 0.0 && syy > 0.0 ? std::norm(sxy) / (sxx * syy) : 0.0;
  t.h = t.h1;
  double rr = 0.0;
  for (size_t i = 0; i < p; ++i) rr += std::norm(s.y[i] - t.h1 * s.x[i]);
  set_band(t, sxx > 0.0 ? rr / static_cast<double>(p - 1) / sxx : 0.0, static_cast<int>(p), band_level);
  return t;
}

std::vector<int> line_bins(const SweepRecord& r) {
  const auto& pl = r.plan;
  const int n = static_cast<int>(pl.samples_per_period);
  if (!(r.rate_hz > 0.0) || !std::isfinite(r.rate_hz)) throw std::invalid_argument("sweep record: rate_hz must be > 0");
  if (n < 4) throw std::invalid_argument("sweep record: plan.samples_per_period must be >= 4");
  if (pl.recorded_periods < 2) throw std::invalid_argument("sweep record: plan.recorded_periods must be >= 2 (averages)");
  if (pl.frequencies_hz.empty()) throw std::invalid_argument("sweep record: plan.frequencies_hz is empty");
  std::vector<int> bins;
  for (double f : pl.frequencies_hz) {
    const double k = f * n / r.rate_hz;
    const long kr = std::lround(k);
    if (!std::isfinite(k) || std::abs(k - static_cast<double>(kr)) > 1e-6 || kr <= 0 || 2 * kr >= n)
      throw std::invalid_argument(io::printf_text("sweep record: line %.9g Hz is not a bin of the %d-sample period at %.9g Hz "
                                                  "(k = %.6f); the estimate needs leakage-free lines", f, n, r.rate_hz, k));
    bins.push_back(static_cast<int>(kr));
  }
  const size_t steps = pl.kind == ExcitationKind::stepped_sine ? pl.frequencies_hz.size() : 1;
  const size_t need = steps * pl.recorded_periods * static_cast<size_t>(n);
  for (const auto& a : r.axes) {
    for (const auto* v : {&a.excitation_a, &a.controller_output_a, &a.summing_point_a, &a.sensor_m})
      if (v->size() != need)
        throw std::invalid_argument(io::printf_text("sweep record: axis %d holds %zu samples per signal, the plan needs %zu", a.axis,
                                                    v->size(), need));
    if (a.axis < 0 || a.axis > 3) throw std::invalid_argument(io::printf_text("sweep record: axis %d is not a control axis 0..3", a.axis));
  }
  return bins;
}

SweepEstimate estimate_sweep(const SweepRecord& r, const EstimateOptions& o) {
  if (!(o.band_level > 0.0 && o.band_level < 1.0)) throw std::invalid_argument("sweep estimate: band_level must lie in (0, 1)");
  const std::vector<int> bins = line_bins(r);
  const int n = static_cast<int>(r.plan.samples_per_period);
  const int p = static_cast<int>(r.plan.recorded_periods);
  const bool stepped = r.plan.kind == ExcitationKind::stepped_sine;
  SweepEstimate out;
  out.periods = p;
  out.band_basis = io::printf_text("period-to-period scatter over %d periods, Student t (%d dof), %.0f %% two-sided", p, 2 * (p - 1),
                                   100.0 * o.band_level);
  PeriodDft dft(n);
  const size_t lines = bins.size(), blocks = stepped ? lines : 1;
  for (const auto& a : r.axes) {
    AxisEstimate ax;
    ax.axis = a.axis;
    ax.min_coherence_s = 1.0;
    std::vector<double> minus_uc(a.controller_output_a.size());
    for (size_t i = 0; i < minus_uc.size(); ++i) minus_uc[i] = -a.controller_output_a[i];
    // spec[signal][line][period]: e, u, -u_c, y.
    std::array<std::vector<std::vector<cd>>, 4> spec;
    for (auto& sg : spec) sg.assign(lines, std::vector<cd>(static_cast<size_t>(p)));
    const std::array<const std::vector<double>*, 4> src{&a.excitation_a, &a.summing_point_a, &minus_uc, &a.sensor_m};
    std::vector<cd> tmp;
    for (size_t blk = 0; blk < blocks; ++blk)
      for (int q = 0; q < p; ++q) {
        const size_t at = (blk * static_cast<size_t>(p) + static_cast<size_t>(q)) * static_cast<size_t>(n);
        for (size_t k = 0; k < 4; ++k) {
          dft.at(*src[k], at, bins, tmp);
          for (size_t l = 0; l < lines; ++l)
            if (!stepped || l == blk) spec[k][l][static_cast<size_t>(q)] = tmp[l];
        }
      }
    for (size_t l = 0; l < lines; ++l) {
      const std::vector<cd>& e = spec[0][l];
      const std::vector<cd>& u = spec[1][l];
      const std::vector<cd>& t = spec[2][l];
      const std::vector<cd>& y = spec[3][l];
      LineEstimate le;
      le.f_hz = r.plan.frequencies_hz[l];
      le.s = h1_h2({e, u});
      le.t = h1_h2({e, t});
      {
        // S, T: H1 on e, band with the level asked for.
        double rs = 0.0, rt = 0.0, ee = 0.0;
        for (int q = 0; q < p; ++q) {
          rs += std::norm(u[static_cast<size_t>(q)] - le.s.h1 * e[static_cast<size_t>(q)]);
          rt += std::norm(t[static_cast<size_t>(q)] - le.t.h1 * e[static_cast<size_t>(q)]);
          ee += std::norm(e[static_cast<size_t>(q)]);
        }
        if (!(ee > 0.0))
          throw std::invalid_argument(io::printf_text("sweep record: axis %d has no excitation at %.6g Hz", a.axis, le.f_hz));
        set_band(le.s, rs / (p - 1) / ee, p, o.band_level);
        set_band(le.t, rt / (p - 1) / ee, p, o.band_level);
      }
      le.g = referenced(e, u, y, o.band_level);
      ax.min_coherence_s = std::min(ax.min_coherence_s, le.s.coherence);
      ax.lines.push_back(le);
    }
    std::sort(ax.lines.begin(), ax.lines.end(), [](const LineEstimate& x1, const LineEstimate& x2) { return x1.f_hz < x2.f_hz; });
    PeakEstimate& pk = ax.peak;
    for (const auto& le : ax.lines) {
      if (le.s.coherence < o.peak_min_coherence) continue;
      if (!pk.found || std::abs(le.s.h) > pk.peak) {
        pk.found = true;
        pk.peak = std::abs(le.s.h);
        pk.lo = le.s.mag_lo;
        pk.hi = le.s.mag_hi;
        pk.frequency_hz = le.f_hz;
      }
    }
    if (pk.found) {
      pk.zone = zone_of(pk.peak);
      pk.zone_lo = zone_of(pk.lo);
      pk.zone_hi = zone_of(pk.hi);
      const std::string span = pk.zone_lo == pk.zone_hi ? std::string() : " (band " + pk.zone_lo + "-" + pk.zone_hi + ")";
      pk.statement = pk.zone + span + io::printf_text(", %.3g [%.3g, %.3g] at %.4g Hz", pk.peak, pk.lo, pk.hi, pk.frequency_hz);
    } else {
      pk.statement = io::printf_text("no line with S coherence >= %.2f", o.peak_min_coherence);
    }
    out.axes.push_back(std::move(ax));
  }
  return out;
}

}  // namespace amb::host::sweep
