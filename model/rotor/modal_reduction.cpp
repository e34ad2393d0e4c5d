#include "model/rotor/modal_reduction.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace amb::model::rotor {
namespace {

std::vector<double> sqrt_sorted(const Eigen::VectorXd& w2) {
  std::vector<double> f(static_cast<size_t>(w2.size()));
  for (Eigen::Index i = 0; i < w2.size(); ++i) f[static_cast<size_t>(i)] = std::sqrt(std::max(0.0, w2(i)));
  std::sort(f.begin(), f.end());
  return f;
}

}  // namespace

ReducedRotor modal_basis(const RotorModel& m, const RotorParams& p) {
  detail::count_eigen_solve();
  // K and M are symmetric, M positive definite: the generalized solver returns
  // M-orthonormal eigenvectors with ascending eigenvalues.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(m.planar_stiffness, m.planar_mass);
  const int total = static_cast<int>(m.planar_mass.rows());
  ReducedRotor r;
  r.modes = total;
  r.shapes = es.eigenvectors();
  r.omega2 = es.eigenvalues();
  // Rigid-body eigenvalues come out as +-round-off; a negative one would be unstable.
  const double scale = std::max(1.0, std::abs(es.eigenvalues()(total - 1)));
  for (int i = 0; i < total; ++i)
    if (r.omega2(i) < 1e-12 * scale) r.omega2(i) = 0.0;
  r.damping = p.rayleigh_alpha_1_per_s + p.rayleigh_beta_s * r.omega2.array();
  r.polar = r.shapes.transpose() * m.planar_polar * r.shapes;
  r.polar = 0.5 * (r.polar + r.polar.transpose()).eval();
  return r;
}

ReducedRotor truncate_basis(const ReducedRotor& basis, const RotorModel& m, int modes_per_plane) {
  const int total = basis.modes;
  const int k = (modes_per_plane <= 0 || modes_per_plane > total) ? total : modes_per_plane;
  if (k == total) return basis;
  ReducedRotor r;
  r.modes = k;
  r.shapes = basis.shapes.leftCols(k);
  r.omega2 = basis.omega2.head(k);
  r.damping = basis.damping.head(k);
  // Recomputed from the kept shapes (not a block of the full product) so that the result is
  // bit-identical to a reduction solved for k modes directly.
  r.polar = r.shapes.transpose() * m.planar_polar * r.shapes;
  r.polar = 0.5 * (r.polar + r.polar.transpose()).eval();
  return r;
}

ReducedRotor reduce_rotor(const RotorModel& m, const RotorParams& p, int modes_per_plane) {
  return truncate_basis(modal_basis(m, p), m, modes_per_plane);
}

Eigen::RowVectorXd modal_interpolation(const RotorModel& m, const ReducedRotor& r, double axial_m) {
  return planar_interpolation(m, axial_m) * r.shapes;
}

std::vector<double> free_free_frequencies_rad_s(const RotorModel& m) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(m.planar_stiffness, m.planar_mass,
                                                               Eigen::EigenvaluesOnly);
  return sqrt_sorted(es.eigenvalues());
}

std::vector<double> supported_frequencies_rad_s(const RotorModel& m, const std::vector<PointSpring>& springs,
                                                const ReducedRotor* r) {
  if (r == nullptr) {
    Eigen::MatrixXd k = m.planar_stiffness;
    for (const auto& s : springs) {
      const Eigen::RowVectorXd n = planar_interpolation(m, s.axial_m);
      k += s.stiffness_n_per_m * n.transpose() * n;
    }
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(k, m.planar_mass, Eigen::EigenvaluesOnly);
    return sqrt_sorted(es.eigenvalues());
  }
  Eigen::MatrixXd k = r->omega2.asDiagonal();
  for (const auto& s : springs) {
    const Eigen::RowVectorXd b = modal_interpolation(m, *r, s.axial_m);
    k += s.stiffness_n_per_m * b.transpose() * b;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(k, Eigen::EigenvaluesOnly);
  return sqrt_sorted(es.eigenvalues());
}

ModalConvergence check_modal_convergence(const RotorModel& m, const RotorParams& p,
                                         const std::vector<PointSpring>& springs, int frequencies_checked,
                                         int max_modes, double tolerance) {
  ModalConvergence c;
  const std::vector<double> full = supported_frequencies_rad_s(m, springs);
  const int n = std::min<int>(frequencies_checked, static_cast<int>(full.size()));
  c.reference_rad_s.assign(full.begin(), full.begin() + n);
  for (int k = n; k <= max_modes && k <= static_cast<int>(full.size()); ++k) {
    const ReducedRotor r = reduce_rotor(m, p, k);
    const std::vector<double> red = supported_frequencies_rad_s(m, springs, &r);
    double worst = 0.0;
    for (int i = 0; i < n; ++i)
      worst = std::max(worst, std::abs(red[static_cast<size_t>(i)] - full[static_cast<size_t>(i)]) /
                                  full[static_cast<size_t>(i)]);
    c.modes.push_back(k);
    c.max_relative_error.push_back(worst);
    if (c.modes_needed < 0 && worst <= tolerance) c.modes_needed = k;
  }
  return c;
}

Eigen::VectorXd modal_gravity_load(const RotorModel& m, const ReducedRotor& r, double gravity_m_s2) {
  Eigen::VectorXd t = Eigen::VectorXd::Zero(2 * m.node_count);
  for (int n = 0; n < m.node_count; ++n) t(2 * n) = 1.0;
  return -gravity_m_s2 * (r.shapes.transpose() * (m.planar_mass * t));
}

}  // namespace amb::model::rotor
