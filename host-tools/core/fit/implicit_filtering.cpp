#include "host-tools/core/fit/implicit_filtering.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>

namespace amb::host::fit {

std::string ImplicitFilteringOptions::check() const {
  if (doe_points < 2) return "doe_points must be >= 2";
  if (!(initial_stencil > 0.0 && initial_stencil <= 0.5)) return "initial_stencil must be in (0, 0.5]";
  if (!(min_stencil > 0.0 && min_stencil < initial_stencil)) return "min_stencil must be in (0, initial_stencil)";
  if (max_evaluations < 1) return "max_evaluations must be >= 1";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (max_backtracks < 0) return "max_backtracks must be >= 0";
  if (threads < 1) return "threads must be >= 1";
  return {};
}

namespace {

using Vec = Eigen::VectorXd;

class Evaluator {
 public:
  Evaluator(const CostFunction& f, const Vec& lo, const Vec& hi, int threads, int budget)
      : f_(f), lo_(lo), hi_(hi), threads_(threads), budget_(budget) {}
  Vec unscale(const Vec& z) const { return lo_ + z.cwiseProduct(hi_ - lo_); }
  int used() const { return used_; }
  int left() const { return budget_ - used_; }
  // Evaluate the scaled points (as many as the budget allows; the rest get +inf).
  std::vector<double> run(const std::vector<Vec>& z) {
    const size_t n = std::min(z.size(), static_cast<size_t>(std::max(0, left())));
    std::vector<double> out(z.size(), std::numeric_limits<double>::infinity());
    std::atomic<size_t> next{0};
    auto work = [&](int worker) {
      for (size_t i = next++; i < n; i = next++) {
        const Vec x = unscale(z[i]);
        out[i] = f_(std::vector<double>(x.data(), x.data() + x.size()), worker);
      }
    };
    const int nt = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads_), std::max<size_t>(n, 1)));
    std::vector<std::thread> pool;
    for (int t = 1; t < nt; ++t) pool.emplace_back(work, t);
    work(0);
    for (auto& t : pool) t.join();
    used_ += static_cast<int>(n);
    return out;
  }

 private:
  const CostFunction& f_;
  Vec lo_, hi_;
  int threads_, budget_, used_ = 0;
};

Vec project(Vec z) { return z.cwiseMax(0.0).cwiseMin(1.0); }

}  // namespace

ImplicitFilteringSummary implicit_filtering(const CostFunction& f, const std::vector<double>& lower,
                                            const std::vector<double>& upper, const ImplicitFilteringOptions& o,
                                            const ProgressFunction& progress) {
  if (const std::string e = o.check(); !e.empty()) throw std::invalid_argument("implicit filtering: " + e);
  const int n = static_cast<int>(lower.size());
  if (n < 1 || upper.size() != lower.size()) throw std::invalid_argument("implicit filtering: bounds must be non-empty and of equal length");
  Vec lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    lo(i) = lower[static_cast<size_t>(i)];
    hi(i) = upper[static_cast<size_t>(i)];
    if (!(hi(i) > lo(i))) throw std::invalid_argument("implicit filtering: upper bound must exceed lower bound");
  }
  Evaluator ev(f, lo, hi, o.threads, o.max_evaluations);
  ImplicitFilteringSummary s;

  // Design of experiments.
  std::vector<Vec> doe;
  if (n == 1) {
    for (int k = 0; k < o.doe_points; ++k) doe.push_back(Vec::Constant(1, (k + 0.5) / o.doe_points));
  } else {
    const int pts = o.doe_points * n;
    std::mt19937 rng(o.seed);
    std::vector<std::vector<int>> perm(static_cast<size_t>(n));
    for (auto& p : perm) {
      for (int k = 0; k < pts; ++k) p.push_back(k);
      std::shuffle(p.begin(), p.end(), rng);
    }
    for (int k = 0; k < pts; ++k) {
      Vec z(n);
      for (int i = 0; i < n; ++i) z(i) = (perm[static_cast<size_t>(i)][static_cast<size_t>(k)] + 0.5) / pts;
      doe.push_back(z);
    }
  }
  const auto doe_cost = ev.run(doe);
  size_t best = 0;
  for (size_t k = 1; k < doe.size(); ++k)
    if (doe_cost[k] < doe_cost[best]) best = k;
  Vec x = doe[best];
  double fx = doe_cost[best];
  s.cost_history.push_back(fx);

  double h = o.initial_stencil;
  Eigen::MatrixXd hess = Eigen::MatrixXd::Identity(n, n);
  Vec g_prev, x_prev;
  bool have_prev = false;
  s.stop_reason = "iteration cap";
  for (s.iterations = 1; s.iterations <= o.max_iterations; ++s.iterations) {
    if (h < o.min_stencil) {
      s.converged = true;
      s.stop_reason = "stencil below min_stencil (minimum resolved)";
      break;
    }
    if (ev.left() < 2 * n) {
      s.stop_reason = "evaluation budget spent";
      break;
    }
    s.stencil_history.push_back(h);
    // Stencil (one-sided where a bound cuts it).
    std::vector<Vec> pts;
    for (int i = 0; i < n; ++i)
      for (int sgn : {1, -1}) {
        Vec z = x;
        z(i) = std::clamp(x(i) + sgn * h, 0.0, 1.0);
        pts.push_back(z);
      }
    const auto fs = ev.run(pts);
    Vec g(n);
    size_t best_s = 0;
    for (size_t k = 1; k < pts.size(); ++k)
      if (fs[k] < fs[best_s]) best_s = k;
    for (int i = 0; i < n; ++i) {
      const double zp = pts[static_cast<size_t>(2 * i)](i), zm = pts[static_cast<size_t>(2 * i + 1)](i);
      const double fp = zp > x(i) ? fs[static_cast<size_t>(2 * i)] : fx, fm = zm < x(i) ? fs[static_cast<size_t>(2 * i + 1)] : fx;
      const double span = std::max(zp, x(i)) - std::min(zm, x(i));
      g(i) = span > 0.0 ? (fp - fm) / span : 0.0;
    }
    if (!(fs[best_s] < fx)) {
      // Stencil failure: the function's variation at this scale is noise; look closer.
      h *= 0.5;
      ++s.stencil_failures;
      s.cost_history.push_back(fx);
      if (progress) progress(s.iterations, fx, h);
      continue;
    }
    // BFGS update from the previous iterate's gradient (skipped unless curvature > 0).
    if (have_prev) {
      const Vec sv = x - x_prev, yv = g - g_prev;
      const double sy = sv.dot(yv);
      if (sy > 1e-12 * sv.norm() * yv.norm()) {
        const Vec hs = hess * sv;
        hess += yv * yv.transpose() / sy - hs * hs.transpose() / sv.dot(hs);
      }
    }
    x_prev = x;
    g_prev = g;
    have_prev = true;
    // Projected line search along the quasi-Newton direction, step at most the box size.
    Vec d = -hess.ldlt().solve(g);
    if (!d.allFinite() || d.dot(g) >= 0.0) d = -g;
    if (d.norm() > 1.0) d *= 1.0 / d.norm();
    Vec x_new = pts[best_s];
    double f_new = fs[best_s];
    double lambda = 1.0;
    for (int b = 0; b <= o.max_backtracks && ev.left() > 0; ++b, lambda *= 0.5) {
      const Vec z = project(x + lambda * d);
      if ((z - x).norm() < 1e-3 * h) break;
      const double fz = ev.run({z})[0];
      if (fz < f_new) {
        x_new = z;
        f_new = fz;
        break;
      }
    }
    x = x_new;
    fx = f_new;
    s.cost_history.push_back(fx);
    if (progress) progress(s.iterations, fx, h);
  }
  s.iterations = std::min(s.iterations, o.max_iterations);
  const Vec xu = ev.unscale(x);
  s.x.assign(xu.data(), xu.data() + n);
  s.cost = fx;
  s.evaluations = ev.used();
  return s;
}

}  // namespace amb::host::fit
