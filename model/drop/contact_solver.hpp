#pragma once
// Contact impulses of one Moreau-Jean step of the drop model (seed 000 section 3.3): two
// auxiliary bearings, each a unilateral rigid contact (Signorini on velocity level with
// Newton's impact law) with Coulomb friction in its one tangential direction, plus the
// dry bearing-drag torque of each inner ring (a one-dimensional friction element on the
// ring's spin DOF). Solved by projected Gauss-Seidel on the 6 x 6 Delassus operator.
//
// Unknown impulses (N s, resp. N m s for the drag): L = [N0, T0, N1, T1, D0, D1].
// Local velocities: y+ = y_free + Del L (m/s, resp. rad/s for the drag rows), y- before the
// step. Laws (all on the step's impulse level):
//  * normal k (active only): 0 <= N_k  _|_  y+_N + e_k y-_N >= 0, with e_k = restitution when
//    the contact approaches (y-_N <= 0) and e_k = 1 when it already separates (a separating
//    contact may be held, never reversed);
//  * friction k: Coulomb on the step-average slip w = (y+_T + y-_T) / 2:
//    |T_k| <= mu N_k, T_k w <= 0, |T_k| < mu N_k => w = 0;
//  * drag k: |D_k| <= drag_bound_k (torque x h), same law on the average ring speed.
// With these laws every impulse does non-positive work on the step-average velocity, which
// is the work the energy-conserving (midpoint) smooth step sees: the solver cannot create
// energy (proof in docs/drop-model.md; test in tests/drop).
// Real time: fixed-size, no allocation, bounded iterations.
#include <algorithm>
#include <cmath>
#include <array>

#include <Eigen/Core>

namespace amb::model::drop {

inline constexpr int k_contact_unknowns = 6;
using LocalVec = Eigen::Matrix<double, k_contact_unknowns, 1>;
using LocalMat = Eigen::Matrix<double, k_contact_unknowns, k_contact_unknowns>;

struct ContactProblem {
  LocalMat delassus;               ///< W^T A^-1 W, local velocity per unit impulse
  LocalVec free_velocity;          ///< y_free: end-of-step local velocities without impulses
  LocalVec pre_velocity;           ///< y-: local velocities at the start of the step
  std::array<bool, 2> active{};    ///< contact k closed (predicted gap <= 0)
  std::array<double, 2> friction_coefficient{};  ///< mu_k, 1
  std::array<double, 2> drag_bound_n_m_s{};       ///< ring drag torque x h, N m s (>= 0)
  double restitution = 0.0;        ///< Newton coefficient e_n in [0, 1]
};

struct ContactSolverOptions {
  double tolerance_m_s = 1e-10;    ///< stop when no impulse update changes its local velocity by more, m/s
  int max_iterations = 200;        ///< Gauss-Seidel sweep cap
};

struct ContactSolution {
  LocalVec impulse;                ///< L (see file comment)
  LocalVec post_velocity;          ///< y+ = y_free + Del L
  int iterations = 0;              ///< sweeps done
  bool converged = false;          ///< tolerance met within the cap
};

/// One Gauss-Seidel sweep over the two ring-drag rows (4, 5) of a local problem (rigid or
/// compliant: any type with `delassus`, `free_velocity`, `pre_velocity` and
/// `drag_bound_n_m_s` as in ContactProblem): each drag impulse is the zero of its ring's
/// average velocity, projected on [-bound, bound]. Returns the largest change of a local
/// velocity it caused, m/s (the solvers' stopping measure).
template <class Problem>
double sweep_ring_drags(const Problem& p, LocalVec& impulse) {
  double change = 0.0;
  for (int k = 0; k < 2; ++k) {
    const int d = 4 + k;
    const double bound = p.drag_bound_n_m_s[static_cast<size_t>(k)];
    const double ddd = p.delassus(d, d);
    const double yd = p.free_velocity(d) + p.delassus.row(d).dot(impulse);
    const double d_new = std::clamp(impulse(d) - (yd + p.pre_velocity(d)) / ddd, -bound, bound);
    change = std::max(change, std::abs(d_new - impulse(d)) * ddd);
    impulse(d) = d_new;
  }
  return change;
}

/// The starting guess of both solvers: `warm` (e.g. last step's impulses), with zero impulse
/// on the rows of an inactive contact whatever it says.
template <class Problem>
ContactSolution warm_start(const Problem& p, const LocalVec& warm) {
  ContactSolution start;
  start.impulse = warm;
  for (int k = 0; k < 2; ++k)
    if (!p.active[static_cast<size_t>(k)]) {
      start.impulse(2 * k) = 0.0;
      start.impulse(2 * k + 1) = 0.0;
    }
  return start;
}

/// The projected Gauss-Seidel frame both contact solvers share: each iteration `contact_rows(s)`
/// updates the contact rows once (returning the largest velocity change it caused, m/s), the
/// ring drags follow, and the iterations stop at o.tolerance_m_s or o.max_iterations; the
/// post-step velocity is then y+ = y_free + D impulse.
template <class Problem, class ContactRows>
ContactSolution gauss_seidel(const Problem& p, const ContactSolverOptions& o, ContactSolution s, ContactRows&& contact_rows) {
  for (s.iterations = 1; s.iterations <= o.max_iterations; ++s.iterations) {
    double change = contact_rows(s);
    change = std::max(change, sweep_ring_drags(p, s.impulse));
    if (change <= o.tolerance_m_s) {
      s.converged = true;
      break;
    }
  }
  s.iterations = std::min(s.iterations, o.max_iterations);
  s.post_velocity = p.free_velocity + p.delassus * s.impulse;
  return s;
}

/// Solve one step's contact problem (see file comment). `warm` is the starting guess
/// (e.g. last step's impulses); inactive contacts get zero impulse whatever it says.
ContactSolution solve_contacts(const ContactProblem& p, const ContactSolverOptions& o, const LocalVec& warm);

}  // namespace amb::model::drop
