#include "model/journal/film_grid_refinement.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace amb::model::journal {
namespace {
struct Change {
  double k = 0.0, c = 0.0;
};
Change change_of(const DynamicCoefficients& a, const DynamicCoefficients& ref) {
  const double nk = std::max(ref.stiffness_n_per_m.norm(), 1e-300), nc = std::max(ref.damping_n_s_per_m.norm(), 1e-300);
  return {(a.stiffness_n_per_m - ref.stiffness_n_per_m).norm() / nk, (a.damping_n_s_per_m - ref.damping_n_s_per_m).norm() / nc};
}
}  // namespace

std::string GridRefinementOptions::check() const {
  if (!(tolerance > 0.0 && tolerance < 0.5)) return "grid tolerance must be in (0, 0.5)";
  if (start_theta < 12) return "start_theta must be >= 12";
  if (start_axial < 2) return "start_axial must be >= 2";
  if (max_theta < start_theta || max_axial < start_axial) return "grid limits must be >= the first grid";
  if (!(relative_step > 0.0 && relative_step < 0.1)) return "relative_step must be in (0, 0.1)";
  return "";
}

double coefficient_change(const DynamicCoefficients& a, const DynamicCoefficients& reference) {
  const Change c = change_of(a, reference);
  return std::max(c.k, c.c);
}

RefinedGrid refine_film_grid(const BearingGeometry& g, const WearParams& wear, const JournalState& s, double spin_rad_s,
                             const GridRefinementOptions& o, const ReynoldsOptions& base) {
  if (const std::string why = o.check(); !why.empty()) throw std::invalid_argument("film grid refinement: " + why);
  const auto t0 = std::chrono::steady_clock::now();
  RefinedGrid r;
  std::map<std::pair<int, int>, DynamicCoefficients> solved;
  auto at = [&](int nt, int nz) -> const DynamicCoefficients& {
    const auto key = std::make_pair(nt, nz);
    if (auto it = solved.find(key); it != solved.end()) return it->second;
    ReynoldsOptions ro = base;
    ro.cells_theta = nt;
    ro.cells_axial = nz;
    const auto t = std::chrono::steady_clock::now();
    ReynoldsSolver solver(g, wear, ro);
    GridLevel lv{nt, nz, perturbation_coefficients(solver, s, spin_rad_s, o.relative_step), 0.0};
    lv.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    r.levels.push_back(lv);
    return solved.emplace(key, lv.coefficients).first->second;
  };
  auto accept = [&](int nt, int nz, Change et, Change ez) {
    r.grid = base;
    r.grid.cells_theta = nt;
    r.grid.cells_axial = nz;
    r.coefficients = at(nt, nz);
    r.error_k = et.k + ez.k;
    r.error_c = et.c + ez.c;
    r.error_theta = std::max(et.k, et.c);
    r.error_axial = std::max(ez.k, ez.c);
    r.error_estimate = std::max(r.error_k, r.error_c);
    r.converged = r.error_estimate <= o.tolerance;
  };
  auto scaled = [](Change c, double f) { return Change{c.k * f, c.c * f}; };
  auto total = [](Change a, Change b) { return std::max(a.k + b.k, a.c + b.c); };

  int nt = o.start_theta, nz = o.start_axial;
  for (;;) {
    const DynamicCoefficients x = at(nt, nz);
    const bool can_t = 2 * nt <= o.max_theta, can_z = 2 * nz <= o.max_axial;
    // Errors of the current grid per direction (4/3 of the change on halving), and of the
    // grid refined in that direction (1/3 of the change).
    Change et_fine{}, ez_fine{}, et_cur{}, ez_cur{};
    if (can_t) {
      const Change d = change_of(x, at(2 * nt, nz));
      et_fine = scaled(d, 1.0 / 3.0);
      et_cur = scaled(d, 4.0 / 3.0);
    }
    if (can_z) {
      const Change d = change_of(x, at(nt, 2 * nz));
      ez_fine = scaled(d, 1.0 / 3.0);
      ez_cur = scaled(d, 4.0 / 3.0);
    }
    if (!can_t && !can_z) {  // limits reached: report the last estimates
      accept(nt, nz, et_cur, ez_cur);
      break;
    }
    if (can_t && total(et_fine, ez_cur) <= o.tolerance && (!can_z || total(et_fine, ez_cur) <= total(et_cur, ez_fine))) {
      accept(2 * nt, nz, et_fine, ez_cur);
      break;
    }
    if (can_z && total(et_cur, ez_fine) <= o.tolerance) {
      accept(nt, 2 * nz, et_cur, ez_fine);
      break;
    }
    if (can_t && can_z && total(et_fine, ez_fine) <= o.tolerance) {
      accept(2 * nt, 2 * nz, et_fine, ez_fine);
      break;
    }
    // Not there yet: refine each direction whose own error is above half the tolerance.
    const bool ref_t = can_t && std::max(et_cur.k, et_cur.c) > 0.5 * o.tolerance;
    const bool ref_z = can_z && std::max(ez_cur.k, ez_cur.c) > 0.5 * o.tolerance;
    if (!ref_t && !ref_z) {
      // Both below half the tolerance but not their sum: refine the larger.
      if (can_t && (!can_z || std::max(et_cur.k, et_cur.c) >= std::max(ez_cur.k, ez_cur.c))) nt *= 2;
      else nz *= 2;
    } else {
      if (ref_t) nt *= 2;
      if (ref_z) nz *= 2;
    }
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace amb::model::journal
