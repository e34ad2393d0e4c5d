#pragma once
// Implicit filtering (Kelley, "Implicit Filtering", SIAM 2011; seed 000 section 2.3): a
// projected quasi-Newton method for bound-constrained minimisation of noisy or
// piecewise-constant functions (a simulated drop's rubbing durations change in steps).
//  * Variables are scaled to the unit box [0, 1]^n.
//  * Start: a design of experiments (seed 002): a grid of doe_points for one unknown, a
//    Latin hypercube of doe_points x n points for more; the best point starts the search.
//  * Each iteration evaluates the central-difference stencil x +- h e_i (one-sided where a
//    bound cuts it). Stencil failure (no stencil point better than x): h halves. Otherwise
//    the difference gradient feeds a BFGS model Hessian and a projected backtracking line
//    search along -H^-1 g (steps 1, 1/2, 1/4, ...; best stencil point as fall-back).
//  * Stops when h < min_stencil (converged: the minimum is resolved to that scale), when
//    the evaluation budget is spent, or after max_iterations.
// Stencil and DOE evaluations are independent: they run on `threads` std::threads.
#include <functional>
#include <string>
#include <vector>

namespace amb::host::fit {

struct ImplicitFilteringOptions {
  int doe_points = 7;             ///< DOE points per unknown (>= 2)
  double initial_stencil = 0.125; ///< first stencil size h, fraction of each bound range
  double min_stencil = 1.0 / 4096; ///< stop when h falls below this, fraction of the range
  int max_evaluations = 200;      ///< budget of cost evaluations
  int max_iterations = 60;        ///< iteration cap
  int max_backtracks = 3;         ///< line-search halvings
  int threads = 2;                ///< worker threads for independent evaluations
  unsigned seed = 7;              ///< Latin-hypercube seed (deterministic)
  std::string check() const;      ///< empty when usable
};

struct ImplicitFilteringSummary {
  std::vector<double> x;             ///< best point found (unscaled)
  double cost = 0.0;                 ///< its cost
  int evaluations = 0;               ///< cost evaluations done
  int iterations = 0;                ///< stencil iterations
  int stencil_failures = 0;          ///< times h was halved
  bool converged = false;            ///< stopped because h < min_stencil
  std::string stop_reason;           ///< why it stopped
  std::vector<double> cost_history;  ///< best cost after the DOE and after each iteration
  std::vector<double> stencil_history; ///< h at each iteration (fraction of the range)
};

/// The cost: x (unscaled, inside the bounds) and the worker index in [0, threads) so that
/// each worker can use its own simulation model. Must be thread-safe across workers.
using CostFunction = std::function<double(const std::vector<double>& x, int worker)>;
/// Progress (may be empty): iteration, best cost, stencil size.
using ProgressFunction = std::function<void(int iteration, double best_cost, double stencil)>;

/// Minimise f over lower <= x <= upper. Throws std::invalid_argument for bad bounds/options.
ImplicitFilteringSummary implicit_filtering(const CostFunction& f, const std::vector<double>& lower,
                                            const std::vector<double>& upper, const ImplicitFilteringOptions& o,
                                            const ProgressFunction& progress = {});

}  // namespace amb::host::fit
