#pragma once
// Finite-element model of a free-free rotor (Timoshenko beams + rigid disks). Built once at
// configure time (allocates); the plant steps a modal reduction of it (modal_reduction.hpp).
//
// Coordinates: z along the rotor from its left end (m), y up, x completing a right-handed
// frame; the rotor spins about +z. Each node has 4 DOFs: x, y (m) and the section rotations
// bx = dx/dz, by = dy/dz (rad, "slopes"). Matrices come in two forms:
//  * planar (2N x 2N, DOFs [w_1, b_1, w_2, b_2, ...]): identical for the x-z and y-z planes;
//  * full (4N x 4N) with q = [x-plane planar DOFs (2N); y-plane planar DOFs (2N)].
// Equation of motion: M q'' + (C + Omega G) q' + K q = f, C = alpha M + beta K,
// G = [[0, P], [-P, 0]] with P the polar rotary-inertia matrix (Omega in rad/s about +z).
//
// Elements: consecutive, left to right; nodes at element ends. An element with
// structural = false is a sleeve (e.g. a lamination stack) on a shaft core: its own section
// adds mass and rotary inertia but no stiffness; the core under it has the section of the
// nearest structural element before it (else after it) and provides mass and stiffness.
#include <Eigen/Core>
#include <vector>

#include "model/plant/plant_params.hpp"

namespace amb::model::rotor {

struct RotorModel {
  int node_count = 0;
  std::vector<double> node_axial_m;     ///< node positions from the left end, m
  std::vector<double> element_phi;      ///< shear parameter used for each element's shape functions
  Eigen::MatrixXd planar_mass;          ///< 2N x 2N, kg / kg m / kg m^2
  Eigen::MatrixXd planar_stiffness;     ///< 2N x 2N, N/m / N / N m
  Eigen::MatrixXd planar_polar;         ///< 2N x 2N polar rotary inertia P, kg m^2
  Eigen::MatrixXd M, K, G, C;           ///< full 4N x 4N matrices (see file comment)
  double mass_kg = 0.0;                 ///< total mass (beams + sleeves + disks), kg
  double polar_inertia_kg_m2 = 0.0;     ///< total polar inertia about the spin axis, kg m^2
  double transverse_inertia_kg_m2 = 0.0;///< about a diameter through the centre of mass, kg m^2
  double centre_of_mass_m = 0.0;        ///< axial position of the centre of mass, m
  double length_m = 0.0;                ///< rotor length, m
};

/// Assemble the rotor. Throws std::invalid_argument when the description is unusable
/// (no structural element, disk not on a node, non-positive sizes).
RotorModel build_rotor_model(const RotorParams& p);

/// Row vector (2N) that maps planar DOFs to the lateral displacement at `axial_m` (m) using
/// the element's Timoshenko shape functions (cubic Hermite when shear is negligible).
/// Positions outside [0, length] are clamped to the ends.
Eigen::RowVectorXd planar_interpolation(const RotorModel& m, double axial_m);

/// Index of the node at `axial_m` within `tol_m`, or -1.
int node_index(const RotorModel& m, double axial_m, double tol_m = 1e-6);

}  // namespace amb::model::rotor
