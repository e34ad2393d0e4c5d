#include "model/drop/contact_solver.hpp"

#include <algorithm>
#include <utility>
#include <cmath>

namespace amb::model::drop {

ContactSolution solve_contacts(const ContactProblem& p, const ContactSolverOptions& o, const LocalVec& warm) {
  // Per-row restitution: e on approach, 1 when already separating (see header).
  std::array<double, 2> e{};
  for (int k = 0; k < 2; ++k) e[static_cast<size_t>(k)] = p.pre_velocity(2 * k) <= 0.0 ? p.restitution : 1.0;

  return gauss_seidel(p, o, warm_start(p, warm), [&](ContactSolution& s) {
    double change = 0.0;
    // Normal rows first, then their friction, then the ring drags: the friction bound
    // depends on the normal impulse just updated.
    for (int k = 0; k < 2; ++k) {
      const size_t ks = static_cast<size_t>(k);
      if (!p.active[ks]) continue;
      const int n = 2 * k, t = 2 * k + 1;
      // Normal: zero of y+_N + e y-_N along its own column, projected on N >= 0.
      const double dnn = p.delassus(n, n);
      double yn = p.free_velocity(n) + p.delassus.row(n).dot(s.impulse);
      const double n_new = std::max(0.0, s.impulse(n) - (yn + e[ks] * p.pre_velocity(n)) / dnn);
      change = std::max(change, std::abs(n_new - s.impulse(n)) * dnn);
      s.impulse(n) = n_new;
      // Friction: zero of the average slip w = (y+_T + y-_T)/2, projected on the cone.
      const double dtt = p.delassus(t, t);
      const double yt = p.free_velocity(t) + p.delassus.row(t).dot(s.impulse);
      const double bound = p.friction_coefficient[ks] * s.impulse(n);
      const double t_new = std::clamp(s.impulse(t) - (yt + p.pre_velocity(t)) / dtt, -bound, bound);
      change = std::max(change, std::abs(t_new - s.impulse(t)) * dtt);
      s.impulse(t) = t_new;
    }
    return change;
  });
}

}  // namespace amb::model::drop
