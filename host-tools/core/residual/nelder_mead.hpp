#pragma once
// Nelder-Mead minimisation through NLopt (LN_NELDERMEAD; unconstrained, callers map bounded
// parameters). Kept as a function so the residual loop states its budget and tolerance once.
#include <functional>
#include <vector>

namespace amb::host::residual {

struct NelderMeadResult {
  std::vector<double> x;
  double value = 0.0;
  int evaluations = 0;
};

/// Minimise f from x0 with initial simplex steps `step` (same units as x), at most
/// `max_evaluations` evaluations; stops when the simplex values agree within `f_tol`.
NelderMeadResult nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                             double step, int max_evaluations, double f_tol = 1e-3);

}  // namespace amb::host::residual
