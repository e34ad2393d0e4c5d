#include "host-tools/core/residual/steady_data.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fftw3.h>
#include <stdexcept>

#include "model/amb/amb_force.hpp"

namespace amb::host::residual {
namespace {

constexpr double k_two_pi = 2.0 * M_PI;

// Least-squares basis over len samples at fs_hz: the mean and the speed orders 1..k_orders at
// spin_hz (cos, sin); the mean alone when spin_hz <= 0.
Eigen::MatrixXd order_basis(double spin_hz, double fs_hz, size_t len) {
  const int ncol = 1 + 2 * (spin_hz > 0 ? k_orders : 0);
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(len), ncol);
  for (size_t i = 0; i < len; ++i) {
    const double t = static_cast<double>(i) / fs_hz;
    basis(static_cast<Eigen::Index>(i), 0) = 1.0;
    for (int h = 1; 2 * h < ncol; ++h) {
      basis(static_cast<Eigen::Index>(i), 2 * h - 1) = std::cos(k_two_pi * h * spin_hz * t);
      basis(static_cast<Eigen::Index>(i), 2 * h) = std::sin(k_two_pi * h * spin_hz * t);
    }
  }
  return basis;
}


// Power of the displacement channels at f (sum of |DFT|^2).
double line_power(const std::array<std::vector<double>, k_channels>& w, double fs, double f) {
  double p = 0.0;
  for (int c = 0; c < 4; ++c) {
    std::complex<double> s = 0.0;
    const auto& x = w[static_cast<size_t>(c)];
    const std::complex<double> step = std::exp(std::complex<double>(0.0, -k_two_pi * f / fs));
    std::complex<double> ph = 1.0;
    for (double v : x) {
      s += v * ph;
      ph *= step;
    }
    p += std::norm(s);
  }
  return p;
}

}  // namespace

ChannelMap match_channels(const LoadedEvent& r) {
  ChannelMap m;
  for (const auto* group : {&r.displacement, &r.current})
    for (const auto& c : *group) {
      const int k = c.rig_index + (group == &r.current ? 4 : 0);
      if (c.rig_index >= 0 && c.rig_index < 4 && m.channel[static_cast<size_t>(k)] == nullptr) m.channel[static_cast<size_t>(k)] = &c.values;
      else m.unmatched.push_back(c.name);
    }
  for (const auto& c : r.other) m.unmatched.push_back(c.name);
  for (int k = 0; k < k_channels; ++k)
    if (m.channel[static_cast<size_t>(k)] == nullptr)
      throw std::runtime_error("event " + r.source + ": no " + (k < 4 ? "displacement channel at the rig's sensor " : "current channel at the rig's actuator axis ") +
                               std::to_string(k % 4));
  if (!r.speed_hz.empty()) m.speed_hz = &r.speed_hz;
  return m;
}

LoadedEvent slice_event(const LoadedEvent& r, size_t begin, size_t end) {
  LoadedEvent s = r;
  end = std::min(end, r.samples());
  begin = std::min(begin, end);
  auto cut = [&](std::vector<double>& v) {
    if (v.size() == r.samples()) v.assign(v.begin() + static_cast<long>(begin), v.begin() + static_cast<long>(end));
  };
  for (auto* g : {&s.displacement, &s.current, &s.current_demand, &s.other})
    for (auto& c : *g) cut(c.values);
  cut(s.speed_hz);
  cut(s.t_s);
  s.trigger_index = r.trigger_index >= begin && r.trigger_index < end ? r.trigger_index - begin : 0;
  return s;
}

SteadyData extract_steady(const LoadedEvent& r, const board::BoardConfig& b, const SteadyOptions& o) {
  SteadyData d;
  d.fs_hz = r.sample_rate_hz;
  const ChannelMap map = match_channels(r);
  d.unmatched = map.unmatched;
  const size_t n = r.samples();
  const auto col = [&](int c) -> const std::vector<double>& { return map[c]; };

  // Rest segment: leading samples with every coil current ~0 (amplifiers off).
  double lim = 1e9;
  for (const auto& a : b.plant.amb) lim = std::min(lim, a.coil_current_limit_a);
  size_t rest_end = 0;
  while (rest_end < n) {
    bool off = true;
    for (int c = 4; c < 8; ++c) off = off && std::abs(col(c)[rest_end]) < 1e-3 * lim;
    if (!off) break;
    ++rest_end;
  }
  const size_t guard = static_cast<size_t>(0.01 * d.fs_hz);
  if (rest_end > 2 * guard + static_cast<size_t>(0.05 * d.fs_hz)) {
    d.has_rest = true;
    const size_t a = guard, e = rest_end - guard;
    d.rest_len = e - a;
    for (int k = 0; k < 4; ++k) {
      double s = 0.0, s2 = 0.0;
      for (size_t i = a; i < e; ++i) s += col(k)[i];
      const double m = s / static_cast<double>(e - a);
      for (size_t i = a; i < e; ++i) s2 += (col(k)[i] - m) * (col(k)[i] - m);
      d.rest_mean_m[static_cast<size_t>(k)] = m;
      d.rest_std_m[static_cast<size_t>(k)] = std::sqrt(s2 / static_cast<double>(e - a - 1));
    }
  }

  // Steady window: the last window_s seconds.
  d.window_len = std::min(n, static_cast<size_t>(o.window_s * d.fs_hz));
  d.window_start = n - d.window_len;
  d.window_s = static_cast<double>(d.window_len) / d.fs_hz;
  if (d.window_len < static_cast<size_t>(4 * o.segment_s * d.fs_hz))
    throw std::runtime_error("event " + r.source + ": too short for a steady window");
  for (int c = 0; c < k_channels; ++c)
    d.window[static_cast<size_t>(c)].assign(col(c).begin() + static_cast<long>(d.window_start), col(c).end());
  double nominal = r.speed_at_trigger_hz.value_or(0.0);
  if (map.speed_hz != nullptr) {
    double s = 0.0;
    for (size_t i = d.window_start; i < n; ++i) s += (*map.speed_hz)[i];
    nominal = s / static_cast<double>(d.window_len);
  }
  // Refine the speed on the displacement lines (the speed channel may be an estimate).
  if (nominal > 0.0) {
    double best = nominal, bp = -1.0;
    for (int it = 0; it < 3; ++it) {
      const double span = (it == 0 ? 0.01 * nominal : bp > 0 ? 0.2 / d.window_s / std::pow(4.0, it - 1) : 0.0);
      const double centre = best;
      for (int g = -20; g <= 20; ++g) {
        const double f = centre + span * g / 20.0;
        const double p = line_power(d.window, d.fs_hz, f);
        if (p > bp) { bp = p; best = f; }
      }
    }
    d.spin_hz = best;
  }

  // Least squares: mean + orders, per channel.
  const Eigen::MatrixXd basis = order_basis(d.spin_hz, d.fs_hz, d.window_len);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(basis.transpose() * basis);
  for (int c = 0; c < k_channels; ++c) {
    const Eigen::Map<const Eigen::VectorXd> y(d.window[static_cast<size_t>(c)].data(), static_cast<Eigen::Index>(d.window_len));
    const Eigen::VectorXd coef = ldlt.solve(basis.transpose() * y);
    d.mean[static_cast<size_t>(c)] = coef(0);
    d.rms[static_cast<size_t>(c)] = std::sqrt(y.squaredNorm() / static_cast<double>(d.window_len));
    for (int h = 1; 2 * h < basis.cols(); ++h)
      d.order[static_cast<size_t>(c)][static_cast<size_t>(h - 1)] = std::complex<double>(coef(2 * h - 1), -coef(2 * h));
  }
  d.bands = remainder_bands(d, 0, d.window_len, o);
  return d;
}

std::vector<Band> remainder_bands(const SteadyData& d, size_t begin, size_t len, const SteadyOptions& o) {
  if (begin + len > d.window_len) throw std::runtime_error("remainder_bands: samples beyond the steady window");
  const Eigen::MatrixXd basis = order_basis(d.spin_hz, d.fs_hz, len);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(basis.transpose() * basis);
  std::array<Eigen::VectorXd, k_channels> rest;
  for (int c = 0; c < k_channels; ++c) {
    const Eigen::Map<const Eigen::VectorXd> y(d.window[static_cast<size_t>(c)].data() + begin, static_cast<Eigen::Index>(len));
    rest[static_cast<size_t>(c)] = y - basis * ldlt.solve(basis.transpose() * y);
  }

  // Welch PSD of the remainder (Hann, 50 % overlap).
  const int seg = static_cast<int>(o.segment_s * d.fs_hz);
  if (seg < 2 || len < static_cast<size_t>(seg)) throw std::runtime_error("remainder_bands: fewer samples than one Welch segment");
  const int hop = seg / 2;
  const int nseg = static_cast<int>((len - static_cast<size_t>(seg)) / static_cast<size_t>(hop)) + 1;
  std::vector<double> win(static_cast<size_t>(seg));
  double wsum2 = 0.0;
  for (int i = 0; i < seg; ++i) {
    win[static_cast<size_t>(i)] = 0.5 - 0.5 * std::cos(k_two_pi * i / seg);
    wsum2 += win[static_cast<size_t>(i)] * win[static_cast<size_t>(i)];
  }
  const int nb = seg / 2 + 1;
  std::vector<double> in(static_cast<size_t>(seg));
  std::vector<fftw_complex> out(static_cast<size_t>(nb));
  fftw_plan plan = fftw_plan_dft_r2c_1d(seg, in.data(), out.data(), FFTW_ESTIMATE);
  std::array<std::vector<double>, k_channels> psd;
  for (int c = 0; c < k_channels; ++c) {
    psd[static_cast<size_t>(c)].assign(static_cast<size_t>(nb), 0.0);
    for (int s = 0; s < nseg; ++s) {
      for (int i = 0; i < seg; ++i) in[static_cast<size_t>(i)] = rest[static_cast<size_t>(c)](s * hop + i) * win[static_cast<size_t>(i)];
      fftw_execute(plan);
      for (int k = 0; k < nb; ++k)
        psd[static_cast<size_t>(c)][static_cast<size_t>(k)] +=
            2.0 * (out[static_cast<size_t>(k)][0] * out[static_cast<size_t>(k)][0] + out[static_cast<size_t>(k)][1] * out[static_cast<size_t>(k)][1]) /
            (d.fs_hz * wsum2 * nseg);
    }
  }
  fftw_destroy_plan(plan);

  // Average per band; bins within 2.5 bins of the first 8 speed orders left out.
  std::vector<Band> bands;
  const double df = d.fs_hz / seg;
  const double f_max = std::min(o.f_max_hz, 0.4 * d.fs_hz);
  const double ratio = std::pow(2.0, 1.0 / o.bands_per_octave);
  for (double f = o.f_min_hz; f <= f_max; f *= ratio) {
    const double lo = f / std::sqrt(ratio), hi = f * std::sqrt(ratio);
    Band band;
    int count = 0;
    double fsum = 0.0;
    for (int k = std::max(1, static_cast<int>(std::ceil(lo / df))); k * df < hi && k < nb; ++k) {
      bool near_line = false;
      for (int h = 1; h <= 8 && d.spin_hz > 0; ++h) near_line = near_line || std::abs(k * df - h * d.spin_hz) < 2.5 * df;
      if (near_line) continue;
      for (int c = 0; c < k_channels; ++c) band.psd[static_cast<size_t>(c)] += psd[static_cast<size_t>(c)][static_cast<size_t>(k)];
      fsum += k * df;
      ++count;
    }
    if (count == 0) continue;
    for (auto& p : band.psd) p /= count;
    band.f_hz = fsum / count;
    band.averages = 0.6 * count * nseg;
    bands.push_back(band);
  }
  return bands;
}

}  // namespace amb::host::residual
