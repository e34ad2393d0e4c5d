#pragma once
// Contact impulses of one step of the drop model with a COMPLIANT contact law at the two
// auxiliary bearings (board key contact_law = "hertz" | "linear"; the rigid law is
// contact_solver.hpp). Same unknowns, Delassus operator and velocity convention as
// contact_solver.hpp: L = [N0, T0, N1, T1, D0, D1], y+ = y_free + Del L, y- before the step;
// the normal rows' local velocity is the gap rate (-penetration rate).
//
// Laws, all on the step-average velocities w = (y- + y+) / 2 (the midpoint rule's own):
//  * normal k: the force over the step is the contact law at the midpoint penetration
//      d_mid = d0 + h/2 * p,  p = -w_N (penetration rate),
//      F = max(0, f(d_mid) + c p),  f(d) = K d^e (e = 1.5 Hertz, 1 linear), c >= 0,
//    f linearised about d_lin (the caller's choice, >= 0): f(d_mid) ~ f0 + k_t h/2 p with
//    f0 = f(d_lin) + k_t (d0 - d_lin), k_t = f'(d_lin). So N = h max(0, f0 + g p),
//    g = k_t h / 2 + c: the trapezoidal rule of the linearised spring-damper (A-stable),
//    never pulling. Hunt-Crossley damping enters through the caller's c (= c_lin + alpha f).
//  * friction k: T = -mu N phi(w_T): phi = exact Coulomb (set-valued sign, stick allowed)
//    when slip_regularisation_m_s = 0, else tanh(w_T / eps) (regularised, stated);
//  * ring drag k: exact dry friction |D| <= drag bound on the average ring speed.
// Solved by non-linear Gauss-Seidel over the six rows (each row's 1-D law exactly);
// stop when no update changes its local velocity by more than the tolerance.
// Real time: fixed-size, no allocation, bounded iterations.
#include <array>

#include "model/drop/contact_solver.hpp"

namespace amb::model::drop {

struct CompliantContactProblem {
  LocalMat delassus;                          ///< W^T A^-1 W (as contact_solver.hpp)
  LocalVec free_velocity;                     ///< y_free, m/s (rad/s for drag rows)
  LocalVec pre_velocity;                      ///< y-, m/s (rad/s for drag rows)
  std::array<bool, 2> active{};               ///< contact k may carry force in this step
  std::array<double, 2> force0_n{};           ///< f0 above (elastic force at d0, linearised), N
  std::array<double, 2> force_rate_n_s_m{};   ///< g above (k_t h/2 + c), N s/m
  std::array<double, 2> friction_coefficient{};///< mu_k, 1
  std::array<double, 2> drag_bound_n_m_s{};   ///< ring drag torque x h, N m s (>= 0)
  double step_s = 0.0;                        ///< h, s
  double slip_regularisation_m_s = 0.0;       ///< eps of tanh(w / eps); 0: exact Coulomb, m/s
};

/// Solves the step's impulses (warm start from `warm`).
ContactSolution solve_compliant_contacts(const CompliantContactProblem& p, const ContactSolverOptions& o,
                                         const LocalVec& warm);

}  // namespace amb::model::drop
