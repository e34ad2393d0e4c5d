#pragma once
// Grid refinement of the finite-volume film to a stated accuracy of its dynamic coefficients.
//
// Error estimate (Richardson, second order: the scheme's observed order, tests/journal):
// the K / C of a grid refined in one direction differ from the coarser grid's by about
// 3/4 of the coarser grid's error in that direction, so the refined grid's remaining error in
// that direction is |X_2 - X_1| / 3. The two directions (circumferential, axial) are refined
// separately: on the rig's bearing the axial error dominates (docs/journal-bearing.md, "Grid
// convergence"). Errors are relative matrix norms, ||dK||_F / ||K||_F and the same for C
// (entries of very different size, e.g. a cross-coupling 300x the direct one, do not blow up
// the estimate); the estimate of a grid is the sum of its two directions' estimates, and the
// largest of K's and C's is the one compared with the tolerance.
#include <string>
#include <vector>

#include "model/journal/reynolds_fvm.hpp"

namespace amb::model::journal {

struct GridRefinementOptions {
  double tolerance = 2e-3;     ///< target relative K / C error (Frobenius-norm relative), e.g. 0.002 = 0.2 %
  int start_theta = 36;        ///< first grid, circumferential cells
  int start_axial = 6;         ///< first grid, axial cells (even: the mid-plane symmetry halves the work)
  int max_theta = 1152;        ///< refinement stops here (converged = false if the tolerance is not met)
  int max_axial = 192;
  double relative_step = 1e-2; ///< perturbation step of the coefficients (perturbation_coefficients)
  /// Empty when valid, else the reason.
  std::string check() const;
};

/// One grid solved during the refinement.
struct GridLevel {
  int cells_theta = 0, cells_axial = 0;
  DynamicCoefficients coefficients;
  double seconds = 0.0;        ///< wall time of the coefficients on this grid, s
};

struct RefinedGrid {
  ReynoldsOptions grid;              ///< the accepted grid (cells_theta, cells_axial; other options as given)
  DynamicCoefficients coefficients;  ///< K, C on the accepted grid (not extrapolated)
  double error_theta = 0.0;          ///< estimated relative K/C error of the accepted grid from the circumferential cells
  double error_axial = 0.0;          ///< the same from the axial cells
  double error_estimate = 0.0;       ///< error_theta + error_axial (max over K and C), relative
  double error_k = 0.0, error_c = 0.0;  ///< the estimate for K and for C separately, relative
  bool converged = false;            ///< error_estimate <= tolerance within the grid limits
  std::vector<GridLevel> levels;     ///< every grid solved, in order
  double seconds = 0.0;              ///< wall time of the refinement, s
};

/// Refine the grid at one journal state and speed until the estimated K/C error is below
/// the tolerance. `base` gives the cavitation and quadrature options (its grid is ignored).
/// Throws std::invalid_argument for bad options, geometry or wear (as ReynoldsSolver).
RefinedGrid refine_film_grid(const BearingGeometry& g, const WearParams& wear, const JournalState& s, double spin_rad_s,
                             const GridRefinementOptions& o = {}, const ReynoldsOptions& base = {});

/// Relative change between two coefficient sets: max of ||dK||_F / ||K||_F and ||dC||_F / ||C||_F
/// (relative to `reference`).
double coefficient_change(const DynamicCoefficients& a, const DynamicCoefficients& reference);

}  // namespace amb::model::journal
