#include "host-tools/core/residual/nelder_mead.hpp"

#include <cmath>
#include <algorithm>
#include <limits>

#include <nlopt.hpp>

namespace amb::host::residual {
namespace {

struct Objective {
  const std::function<double(const std::vector<double>&)>* f;
  int evaluations = 0;
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;
};

// NLopt's simplex cannot rank infinite values; an unusable point gets a finite, worse-than-any value.
double call(unsigned n, const double* x, double* /*grad*/, void* data) {
  auto* o = static_cast<Objective*>(data);
  std::vector<double> v(x, x + n);
  double y = (*o->f)(v);
  ++o->evaluations;
  if (!std::isfinite(y)) y = std::numeric_limits<double>::max() / 4.0;
  if (y < o->best) {
    o->best = y;
    o->best_x = v;
  }
  return y;
}

}  // namespace

// NLopt's Nelder-Mead (LN_NELDERMEAD; the maintained implementation the rest of the host's
// optimisation uses), unbounded, initial simplex steps `step`, stopped by the evaluation
// budget or when a step changes the value by less than f_tol (absolute).
NelderMeadResult nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                             double step, int max_evaluations, double f_tol) {
  NelderMeadResult r;
  if (x0.empty()) {
    r.x = x0;
    r.value = f(x0);
    r.evaluations = 1;
    return r;
  }
  Objective o{&f, 0, std::numeric_limits<double>::infinity(), x0};
  nlopt::opt opt(nlopt::LN_NELDERMEAD, static_cast<unsigned>(x0.size()));
  opt.set_min_objective(call, &o);
  opt.set_initial_step(step);
  opt.set_maxeval(std::max(max_evaluations, static_cast<int>(x0.size()) + 2));
  opt.set_ftol_abs(f_tol);
  std::vector<double> x = x0;
  double value = 0.0;
  try {
    opt.optimize(x, value);
  } catch (const std::exception&) {
    // roundoff or a forced stop: the best point seen is still the answer
  }
  r.x = o.best_x;
  r.value = o.best;
  r.evaluations = o.evaluations;
  return r;
}

}  // namespace amb::host::residual
