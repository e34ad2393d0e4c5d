#include "model/bearing/stiffness_identification.hpp"

#include <fftw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace amb::model::bearing {

bool StiffnessIdOptions::valid() const {
  return eta_min > 0 && eta_max > eta_min && fs_hz > 0 && smoothing_hz >= 0 && band_low_hz >= 0 && band_high_hz >= 0 &&
         (band_high_hz == 0 || band_high_hz > band_low_hz) && grid_points >= 3 && eta_tolerance > 0 &&
         max_evaluations >= grid_points && grid_points >= 5 && zoom_spacing > 0 && swarm_size >= 2 && max_iterations >= 1 && visual > 0 && step > 0 &&
         crowding > 0 && prey_tries >= 1 && logistic_mu > 3.5699 && logistic_mu <= 4.0 && logistic_x0 > 0 &&
         logistic_x0 < 1 && afsa_max_evaluations > swarm_size;
}

SpectralCost::SpectralCost(const Hertz4DofParams& base, std::function<double(double)> shaft_speed_hz,
                           const std::vector<double>& measured, double fs_hz, double band_low_hz,
                           double band_high_hz, double smoothing_hz)
    : base_(base), speed_(std::move(shaft_speed_hz)), fs_hz_(fs_hz), n_(measured.size()) {
  if (n_ < 64 || !(fs_hz > 0)) throw std::invalid_argument("measured record too short or fs <= 0");
  const double df = fs_hz / static_cast<double>(n_);
  k0_ = static_cast<size_t>(std::ceil(band_low_hz / df));
  k1_ = band_high_hz > 0 ? std::min(n_ / 2, static_cast<size_t>(std::floor(band_high_hz / df))) : n_ / 2;
  if (k1_ <= k0_ + 2) throw std::invalid_argument("cost band holds no bins");
  smooth_bins_ = std::max<size_t>(1, static_cast<size_t>(std::lround(smoothing_hz / df)));
  fft_in_.resize(n_);
  fft_out_.resize(2 * (n_ / 2 + 1));
  plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(n_), fft_in_.data(),
                               reinterpret_cast<fftw_complex*>(fft_out_.data()), FFTW_ESTIMATE);
  sim_.reserve(n_);
  magnitude(measured, meas_mag_);
}

SpectralCost::~SpectralCost() {
  if (plan_) fftw_destroy_plan(static_cast<fftw_plan>(plan_));
}

void SpectralCost::magnitude(const std::vector<double>& x, std::vector<double>& mag) {
  // Hann window: the records are not periodic in the window; leakage would blur resonances.
  for (size_t i = 0; i < n_; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n_));
    fft_in_[i] = x[i] * w;
  }
  fftw_execute(static_cast<fftw_plan>(plan_));
  const size_t m = k1_ - k0_;
  raw_mag_.resize(m);
  mag.resize(m);
  const double scale = 2.0 / static_cast<double>(n_);
  for (size_t k = k0_; k < k1_; ++k) raw_mag_[k - k0_] = scale * std::hypot(fft_out_[2 * k], fft_out_[2 * k + 1]);
  // Centred moving average by a running sum (window shrinks at the band edges).
  const size_t half = smooth_bins_ / 2;
  double sum = 0.0;
  size_t lo = 0, hi = 0;  // window [lo, hi)
  for (size_t i = 0; i < m; ++i) {
    const size_t want_hi = std::min(m, i + half + 1);
    const size_t want_lo = i > half ? i - half : 0;
    while (hi < want_hi) sum += raw_mag_[hi++];
    while (lo < want_lo) sum -= raw_mag_[lo++];
    mag[i] = sum / static_cast<double>(hi - lo);
  }
}

double SpectralCost::operator()(double eta) {
  if (!(eta > 0)) throw std::invalid_argument("eta must be > 0");
  Hertz4DofParams p = base_;
  p.stiffness_scale = eta;
  Hertz4DofModel model;
  if (!model.configure(p)) throw std::invalid_argument("model parameters out of range");
  simulate_housing_acceleration_into(model, speed_, fs_hz_, static_cast<double>(n_) / fs_hz_ + 0.5 / fs_hz_, sim_);
  sim_.resize(n_);
  magnitude(sim_, sim_mag_);
  ++evaluations_;
  double s = 0.0;
  for (size_t i = 0; i < sim_mag_.size(); ++i) {
    const double d = meas_mag_[i] - sim_mag_[i];
    s += d * d;
  }
  return std::sqrt(s / static_cast<double>(sim_mag_.size()));
}

namespace {

struct EvalCounter {
  SpectralCost& cost;
  int budget;
  double operator()(double eta) { return cost(eta); }
  bool exhausted() const { return cost.evaluations() >= budget; }
};

// Brent's minimiser on [a, b] (golden section + successive parabolic interpolation).
// Returns the best x; `iters` counts evaluations.
double brent_minimise(EvalCounter& f, double a, double b, double x, double fx, double rel_tol, bool& converged) {
  const double golden = 0.3819660112501051;
  double w = x, v = x, fw = fx, fv = fx;
  double d = 0.0, e = 0.0;
  converged = false;
  while (!f.exhausted()) {
    const double m = 0.5 * (a + b);
    const double tol1 = rel_tol * std::abs(x) + 1e-12;
    const double tol2 = 2.0 * tol1;
    if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) {
      converged = true;
      break;
    }
    bool golden_step = true;
    if (std::abs(e) > tol1) {
      // Parabola through (x, fx), (w, fw), (v, fv).
      double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      const double etemp = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * etemp) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = (m - x >= 0) ? tol1 : -tol1;
        golden_step = false;
      }
    }
    if (golden_step) {
      e = (x >= m) ? a - x : b - x;
      d = golden * e;
    }
    const double u = std::abs(d) >= tol1 ? x + d : x + (d >= 0 ? tol1 : -tol1);
    const double fu = f(u);
    if (fu <= fx) {
      if (u >= x) a = x; else b = x;
      v = w; fv = fw;
      w = x; fw = fx;
      x = u; fx = fu;
    } else {
      if (u < x) a = u; else b = u;
      if (fu <= fw || w == x) {
        v = w; fv = fw;
        w = u; fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u; fv = fu;
      }
    }
  }
  return x;
}

StiffnessIdSummary run_brent(SpectralCost& cost, const StiffnessIdOptions& o) {
  EvalCounter f{cost, o.max_evaluations};
  // Zoomed log grid: f(eta) has side minima a few % apart, so Brent alone from one bracket
  // can stall in the wrong one; the grid picks the deepest valley first.
  double la = std::log(o.eta_min), lb = std::log(o.eta_max);
  const auto n = static_cast<size_t>(o.grid_points);
  std::vector<double> grid(n), fg(n);
  size_t best = 0;
  for (;;) {
    for (size_t i = 0; i < n; ++i) {
      grid[i] = std::exp(la + (lb - la) * static_cast<double>(i) / static_cast<double>(n - 1));
      fg[i] = f(grid[i]);
      if (i == 0 || fg[i] < fg[best]) best = i;
    }
    la = std::log(grid[best == 0 ? 0 : best - 1]);
    lb = std::log(grid[std::min(best + 1, n - 1)]);
    const double spacing = std::exp((lb - la) / static_cast<double>(n - 1)) - 1.0;
    if (spacing < o.zoom_spacing || f.exhausted()) break;
  }
  const double a = std::exp(la);
  const double b = std::exp(lb);
  StiffnessIdSummary s;
  bool converged = false;
  s.eta = brent_minimise(f, a, b, grid[best], fg[best], o.eta_tolerance, converged);
  s.cost = cost(s.eta);
  s.converged = converged;
  s.termination = converged ? "Brent: bracket narrower than tolerance" : "Brent: evaluation budget exhausted";
  return s;
}

// Seed 003 section 4.2: AFSA with chaotic logistic initialisation (eq. 10) made uniform (eq. 11).
StiffnessIdSummary run_afsa(SpectralCost& cost, const StiffnessIdOptions& o) {
  const double la = std::log(o.eta_min), lb = std::log(o.eta_max);
  auto eta_of = [&](double u) { return std::exp(la + (lb - la) * std::clamp(u, 0.0, 1.0)); };
  // Food concentration Y = -cost (AFSA maximises).
  auto food = [&](double u) { return -cost(eta_of(u)); };
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const auto n = static_cast<size_t>(o.swarm_size);
  std::vector<double> u(n), y(n);
  double chaos = o.logistic_x0;
  for (size_t i = 0; i < n; ++i) {
    chaos = o.logistic_mu * chaos * (1.0 - chaos);
    u[i] = 2.0 / M_PI * std::asin(std::sqrt(chaos));  // eq. 11
    y[i] = food(u[i]);
  }
  size_t ib = static_cast<size_t>(std::max_element(y.begin(), y.end()) - y.begin());
  double best_u = u[ib], best_y = y[ib];  // bulletin board
  auto move_towards = [&](double from, double to) {
    const double dist = to - from;
    if (std::abs(dist) < 1e-15) return from;
    return std::clamp(from + o.step * uni(rng) * (dist > 0 ? 1.0 : -1.0), 0.0, 1.0);
  };
  int iter = 0;
  for (; iter < o.max_iterations && cost.evaluations() < o.afsa_max_evaluations; ++iter) {
    for (size_t i = 0; i < n; ++i) {
      // Companions within the visual distance.
      int nf = 0;
      double centre = 0.0;
      size_t j_best = i;
      for (size_t j = 0; j < n; ++j) {
        if (j == i || std::abs(u[j] - u[i]) > o.visual) continue;
        ++nf;
        centre += u[j];
        if (j_best == i || y[j] > y[j_best]) j_best = j;
      }
      bool moved = false;
      // Costs are positive, so Y = -cost < 0. The crowding test Y_j / n_f > delta Y_i of the
      // seed is written for positive concentrations; with negative Y it is applied to
      // 1/cost (positive, larger is better): (1/c_j)/n_f > delta (1/c_i).
      auto crowd_ok = [&](double yj) { return nf > 0 && (-1.0 / yj) / nf > o.crowding * (-1.0 / y[i]); };
      if (nf > 0 && j_best != i && y[j_best] > y[i] && crowd_ok(y[j_best])) {  // follow
        u[i] = move_towards(u[i], u[j_best]);
        y[i] = food(u[i]);
        moved = true;
      }
      if (!moved && nf > 0) {  // swarm
        centre /= nf;
        const double yc = food(centre);
        if (yc > y[i] && crowd_ok(yc)) {
          u[i] = move_towards(u[i], centre);
          y[i] = food(u[i]);
          moved = true;
        }
      }
      if (!moved) {  // prey: probe within the visual distance, move towards a better probe
        for (int t = 0; t < o.prey_tries; ++t) {
          const double probe = std::clamp(u[i] + o.visual * (2.0 * uni(rng) - 1.0), 0.0, 1.0);
          const double yp = food(probe);
          if (yp > y[i]) {
            u[i] = move_towards(u[i], probe);
            y[i] = food(u[i]);
            moved = true;
            break;
          }
        }
        if (!moved) {  // random move
          u[i] = std::clamp(u[i] + o.step * (2.0 * uni(rng) - 1.0), 0.0, 1.0);
          y[i] = food(u[i]);
        }
      }
      if (y[i] > best_y) {
        best_y = y[i];
        best_u = u[i];
      }
    }
  }
  StiffnessIdSummary s;
  s.eta = eta_of(best_u);
  s.cost = -best_y;
  s.converged = iter == o.max_iterations;
  s.termination = s.converged ? "AFSA: maximum iterations reached" : "AFSA: evaluation budget exhausted";
  return s;
}

}  // namespace

StiffnessIdSummary identify_stiffness_scale(const Hertz4DofParams& base,
                                            const std::function<double(double t_s)>& shaft_speed_hz,
                                            const std::vector<double>& measured, const StiffnessIdOptions& o) {
  if (!o.valid()) throw std::invalid_argument("StiffnessIdOptions out of range");
  const auto t0 = std::chrono::steady_clock::now();
  SpectralCost cost(base, shaft_speed_hz, measured, o.fs_hz, o.band_low_hz, o.band_high_hz, o.smoothing_hz);
  StiffnessIdSummary s = o.method == EtaMethod::brent ? run_brent(cost, o) : run_afsa(cost, o);
  s.evaluations = cost.evaluations();
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Hertz4DofParams p = base;
  p.stiffness_scale = s.eta;
  Hertz4DofModel m;
  if (m.configure(p)) s.effective_stiffness_n_per_m = m.equivalent_stiffness_n_per_m(m.initial_state());
  return s;
}

}  // namespace amb::model::bearing
