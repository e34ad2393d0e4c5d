#include "host-tools/core/residual/nelder_mead.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace amb::host::residual {

NelderMeadResult nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                             double step, int max_evaluations, double f_tol) {
  const size_t n = x0.size();
  NelderMeadResult r;
  if (n == 0) {
    r.x = x0;
    r.value = f(x0);
    r.evaluations = 1;
    return r;
  }
  std::vector<std::vector<double>> s(n + 1, x0);
  std::vector<double> v(n + 1);
  for (size_t i = 0; i < n; ++i) s[i + 1][i] += step;
  for (size_t i = 0; i <= n; ++i) v[i] = f(s[i]);
  int evals = static_cast<int>(n + 1);
  std::vector<size_t> order(n + 1);
  while (evals < max_evaluations) {
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
    const size_t best = order[0], worst = order[n], second = order[n - 1];
    if (std::abs(v[worst] - v[best]) < f_tol) break;
    std::vector<double> c(n, 0.0);
    for (size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (size_t k = 0; k < n; ++k) c[k] += s[i][k] / static_cast<double>(n);
    auto along = [&](double t) {
      std::vector<double> x(n);
      for (size_t k = 0; k < n; ++k) x[k] = c[k] + t * (s[worst][k] - c[k]);
      return x;
    };
    const auto xr = along(-1.0);
    const double fr = f(xr);
    ++evals;
    if (fr < v[best]) {
      const auto xe = along(-2.0);
      const double fe = f(xe);
      ++evals;
      if (fe < fr) { s[worst] = xe; v[worst] = fe; }
      else { s[worst] = xr; v[worst] = fr; }
    } else if (fr < v[second]) {
      s[worst] = xr;
      v[worst] = fr;
    } else {
      const auto xc = along(fr < v[worst] ? -0.5 : 0.5);
      const double fc = f(xc);
      ++evals;
      if (fc < std::min(fr, v[worst])) {
        s[worst] = xc;
        v[worst] = fc;
      } else {
        for (size_t i = 0; i <= n; ++i) {
          if (i == best) continue;
          for (size_t k = 0; k < n; ++k) s[i][k] = s[best][k] + 0.5 * (s[i][k] - s[best][k]);
          v[i] = f(s[i]);
          ++evals;
        }
      }
    }
  }
  const size_t best = static_cast<size_t>(std::min_element(v.begin(), v.end()) - v.begin());
  r.x = s[best];
  r.value = v[best];
  r.evaluations = evals;
  return r;
}

}  // namespace amb::host::residual
