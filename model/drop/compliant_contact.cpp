#include "model/drop/compliant_contact.hpp"

#include <algorithm>
#include <utility>
#include <cmath>

namespace amb::model::drop {
namespace {

// Friction impulse T in [-b, b] with T = -b tanh((v0 + a T) / eps), a = D_tt / 2 > 0
// (v0: step-average slip without this row's own impulse). g(T) = T + b tanh(.) is strictly
// increasing: safeguarded Newton in the bracket, a fixed maximum of iterations.
double regularised_friction(double v0, double a, double b, double eps) {
  if (b <= 0.0) return 0.0;
  double lo = -b, hi = b;
  double t = std::clamp(-v0 / a, lo, hi);
  for (int it = 0; it < 40; ++it) {
    const double th = std::tanh((v0 + a * t) / eps);
    const double g = t + b * th;
    if (g > 0.0) hi = t; else lo = t;
    const double dg = 1.0 + b * a * (1.0 - th * th) / eps;
    double next = t - g / dg;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - t) <= 1e-13 * b + 1e-18) return next;
    t = next;
  }
  return t;
}

}  // namespace

ContactSolution solve_compliant_contacts(const CompliantContactProblem& p, const ContactSolverOptions& o,
                                         const LocalVec& warm) {
  const double h = p.step_s;
  return gauss_seidel(p, o, warm_start(p, warm), [&](ContactSolution& s) {
    double change = 0.0;
    for (int k = 0; k < 2; ++k) {
      const size_t ks = static_cast<size_t>(k);
      if (!p.active[ks]) continue;
      const int n = 2 * k, t = n + 1;
      // Normal: N = h max(0, f0 + g p), p = -(y- + y+)/2, y+ linear in N along its column.
      const double dnn = p.delassus(n, n);
      const double y_other = p.free_velocity(n) + p.delassus.row(n).dot(s.impulse) - dnn * s.impulse(n);
      const double p0 = -0.5 * (p.pre_velocity(n) + y_other);  // penetration rate without N
      const double g = p.force_rate_n_s_m[ks];
      const double n_new = std::max(0.0, h * (p.force0_n[ks] + g * p0) / (1.0 + 0.5 * h * g * dnn));
      change = std::max(change, std::abs(n_new - s.impulse(n)) * dnn);
      s.impulse(n) = n_new;
      // Friction on the average slip.
      const double dtt = p.delassus(t, t);
      const double yt_other = p.free_velocity(t) + p.delassus.row(t).dot(s.impulse) - dtt * s.impulse(t);
      const double w0 = 0.5 * (p.pre_velocity(t) + yt_other);
      const double bound = p.friction_coefficient[ks] * n_new;
      const double t_new = p.slip_regularisation_m_s > 0.0
                               ? regularised_friction(w0, 0.5 * dtt, bound, p.slip_regularisation_m_s)
                               : std::clamp(-w0 / (0.5 * dtt), -bound, bound);
      change = std::max(change, std::abs(t_new - s.impulse(t)) * dtt);
      s.impulse(t) = t_new;
    }
    return change;
  });
}

}  // namespace amb::model::drop
