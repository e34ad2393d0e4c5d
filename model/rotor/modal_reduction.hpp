#pragma once
// Modal reduction of the free-free rotor: the lowest planar mode shapes (rigid-body modes
// included) of K phi = w^2 M phi. Because the x-z and y-z planes have the same matrices at
// standstill, one set of planar shapes serves both planes; spin couples them through the
// reduced gyroscopic matrix. Mode shapes are mass-normalised, so the reduced mass is I, the
// reduced stiffness diag(w^2) and Rayleigh damping diag(alpha + beta w^2).
#include <Eigen/Core>
#include <vector>

#include "model/rotor/rotor_model.hpp"

namespace amb::model::rotor {

struct ReducedRotor {
  int modes = 0;                 ///< mode shapes kept per lateral plane
  Eigen::MatrixXd shapes;        ///< 2N x modes, mass-normalised planar mode shapes
  Eigen::VectorXd omega2;        ///< free-free eigenvalues, (rad/s)^2, rigid-body modes clamped to 0
  Eigen::VectorXd damping;       ///< modal damping alpha + beta w^2, 1/s
  Eigen::MatrixXd polar;         ///< modes x modes reduced polar matrix Phi^T P Phi (symmetric), 1
};

/// Keep the lowest `modes_per_plane` planar modes (0 or more than available: all of them).
/// Same as truncate_basis(modal_basis(m, p), m, modes_per_plane).
ReducedRotor reduce_rotor(const RotorModel& m, const RotorParams& p, int modes_per_plane);

/// Every planar mode of the rotor (one generalised eigen solve; counted in build_counts()).
ReducedRotor modal_basis(const RotorModel& m, const RotorParams& p);

/// The lowest `modes_per_plane` modes of a complete basis (<= 0 or more than available: all),
/// without a new eigen solve; bit-identical to reduce_rotor with the same count.
ReducedRotor truncate_basis(const ReducedRotor& basis, const RotorModel& m, int modes_per_plane);

/// How often this process has assembled an FE rotor and solved its modal eigenproblem
/// (tests check that a fit or a residual run builds each rig once).
struct BuildCounts {
  long fe_builds = 0;     ///< build_rotor_model calls
  long eigen_solves = 0;  ///< modal eigen solves (modal_basis, reduce_rotor)
};
BuildCounts build_counts();
namespace detail {
void count_fe_build();     ///< called by build_rotor_model
void count_eigen_solve();  ///< called by modal_basis
}  // namespace detail

/// Reduced interpolation row: modal coordinates -> displacement at `axial_m` (m per unit).
Eigen::RowVectorXd modal_interpolation(const RotorModel& m, const ReducedRotor& r, double axial_m);

/// Modal force of gravity acting along -y on the consistent mass: Phi^T M (-g t), with t the
/// unit lateral translation of every node. `gravity_m_s2` >= 0; one entry per kept mode, N.
Eigen::VectorXd modal_gravity_load(const RotorModel& m, const ReducedRotor& r, double gravity_m_s2);

/// Free-free planar natural frequencies of the full FE model, ascending, rad/s.
std::vector<double> free_free_frequencies_rad_s(const RotorModel& m);

/// A linear radial spring at an axial position (used to support the rotor in checks).
struct PointSpring {
  double axial_m = 0.0;              ///< position, m
  double stiffness_n_per_m = 0.0;    ///< N/m
};

/// Planar natural frequencies (rad/s, ascending, undamped, no spin) of the rotor on
/// `springs`: full FE model when `r` is null, else the reduced model.
std::vector<double> supported_frequencies_rad_s(const RotorModel& m, const std::vector<PointSpring>& springs,
                                                const ReducedRotor* r = nullptr);

/// Convergence check of the modal reduction: the lowest `frequencies_checked` frequencies of
/// the spring-supported rotor, reduced with modes = frequencies_checked .. max_modes, are
/// compared with the full FE model. (Free-free frequencies would match trivially: the
/// supports are what a truncated basis represents imperfectly.)
struct ModalConvergence {
  std::vector<double> reference_rad_s;   ///< full-model frequencies checked, rad/s
  std::vector<int> modes;                ///< mode counts tried
  std::vector<double> max_relative_error;///< worst relative error over the checked frequencies
  int modes_needed = -1;                 ///< smallest count within tolerance (-1: none)
};
ModalConvergence check_modal_convergence(const RotorModel& m, const RotorParams& p,
                                         const std::vector<PointSpring>& springs, int frequencies_checked,
                                         int max_modes, double tolerance);

}  // namespace amb::model::rotor
