#pragma once
// One Timoshenko beam element in one lateral plane. DOFs [w1, b1, w2, b2]: translation (m)
// and cross-section rotation (rad, positive like the slope dw/dz) at the left and right node.
// The same matrices serve the x-z and the y-z plane because both rotations are taken as
// slopes (dx/dz, dy/dz), so no sign flips appear between the planes.
#include <Eigen/Core>

#include "model/plant/plant_params.hpp"

namespace amb::model::rotor {

using Mat4 = Eigen::Matrix4d;
using Row4 = Eigen::RowVector4d;

/// Section properties of one element (SI).
struct ElementSection {
  double area_m2 = 0.0;          ///< A
  double second_moment_m4 = 0.0; ///< I about a diameter
  double shear_factor = 0.0;     ///< Timoshenko shear coefficient kappa (Hutchinson, hollow circle)
  double phi = 0.0;              ///< shear parameter 12 E I / (kappa G A L^2) (0 for non-structural)
};

/// Section properties of `e`.
ElementSection element_section(const BeamElement& e);

/// Planar element matrices (per plane). `mass` holds translational + rotary inertia,
/// `polar` the polar rotary-inertia matrix (2 rho I) that forms the gyroscopic matrix.
struct ElementMatrices {
  Mat4 stiffness = Mat4::Zero();   ///< N/m, N, N m (bending + shear), zero if non-structural
  Mat4 mass = Mat4::Zero();        ///< kg, kg m, kg m^2
  Mat4 polar = Mat4::Zero();       ///< kg m^2 (gyroscopic: G = [[0, P], [-P, 0]] between planes)
};

/// Consistent element matrices, integrated exactly from the Timoshenko shape functions.
/// `stiffness_phi` is the shear parameter used for the shape functions (the overlay of a
/// non-structural element uses the shape functions of the structural element it sits on).
ElementMatrices element_matrices(const BeamElement& e, double stiffness_phi, bool with_stiffness);

/// Displacement shape functions N_w at xi = z / L in [0, 1] (w = N_w [w1 b1 w2 b2]^T).
/// For phi = 0 these are the cubic Hermite functions.
Row4 displacement_shape(double xi, double length_m, double phi);

/// Rotation shape functions N_psi at xi (psi = N_psi [w1 b1 w2 b2]^T), rad per DOF unit.
Row4 rotation_shape(double xi, double length_m, double phi);

}  // namespace amb::model::rotor
