#include "model/analysis/half_open_frf.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

namespace amb::model::analysis {
namespace {

using cd = std::complex<double>;

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("half-open FRF model: " + what);
}

}  // namespace

HalfOpenFrf::HalfOpenFrf(const HalfOpenParams& p) : p_(p) {
  RotorParams r = p.rotor;
  require(!r.elements.empty(), "rotor has no elements");
  require(p.element_stiffness_scale.empty() || p.element_stiffness_scale.size() == r.elements.size(),
          "element_stiffness_scale must have one value per element");
  require(p.disk_mass_scale.empty() || p.disk_mass_scale.size() == r.disks.size(), "disk_mass_scale must have one value per disk");
  require(p.disk_inertia_scale.empty() || p.disk_inertia_scale.size() == r.disks.size(),
          "disk_inertia_scale must have one value per disk");
  require(p.modes_kept >= 3, "modes_kept must be at least 3");
  require(p.excited == 0 || p.excited == 1, "excited must be 0 or 1");
  for (size_t e = 0; e < p.element_stiffness_scale.size(); ++e) {
    require(p.element_stiffness_scale[e] > 0.0, "element stiffness scale must be positive");
    r.elements[e].youngs_modulus_pa *= p.element_stiffness_scale[e];
  }
  for (size_t d = 0; d < r.disks.size(); ++d) {
    if (!p.disk_mass_scale.empty()) r.disks[d].mass_kg *= p.disk_mass_scale[d];
    if (!p.disk_inertia_scale.empty()) {
      r.disks[d].transverse_inertia_kg_m2 *= p.disk_inertia_scale[d];
      r.disks[d].polar_inertia_kg_m2 *= p.disk_inertia_scale[d];
    }
  }
  model_ = rotor::build_rotor_model(r);
  length_m_ = model_.length_m;
  Eigen::MatrixXd m = model_.planar_mass;
  for (const auto& a : p.attached) {
    require(a.mass_kg >= 0.0, "attached mass must be >= 0");
    const Eigen::RowVectorXd n = rotor::planar_interpolation(model_, a.axial_m);
    m += a.mass_kg * n.transpose() * n;
  }
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(model_.planar_stiffness, m);
  require(es.info() == Eigen::Success, "free-free eigenproblem failed");
  const int n = std::min<int>(p.modes_kept, static_cast<int>(m.rows()));
  phi_ = es.eigenvectors().leftCols(n);
  int flex = 0;
  for (int k = 0; k < n; ++k) {
    const double w = std::sqrt(std::max(es.eigenvalues()(k), 0.0));
    omega_.push_back(w);
    free_hz_.push_back(w / (2.0 * M_PI));
    if (w < 2.0 * M_PI * 1.0) {
      zeta_.push_back(0.0);  // rigid-body mode
    } else {
      const size_t f = static_cast<size_t>(flex++);
      zeta_.push_back(f < p.flexible_damping_ratio.size() ? p.flexible_damping_ratio[f] : p.default_damping_ratio);
    }
  }
  for (int j = 0; j < 2; ++j) {
    const auto& b = p.bearing[static_cast<size_t>(j)];
    require(b.ki_n_per_a > 0.0 && b.ks_n_per_m >= 0.0 && b.actuator_lag_s >= 0.0, "bearing constants out of range");
    bearing_row_[static_cast<size_t>(j)] = rotor::planar_interpolation(model_, b.axial_m) * phi_;
  }
}

Eigen::VectorXcd HalfOpenFrf::modal_response(double f_hz) const {
  const double w = 2.0 * M_PI * f_hz;
  const cd s(0.0, w);
  const int n = static_cast<int>(omega_.size());
  std::array<int, 2> hidx{-1, -1};
  int dim = n;
  for (int j = 0; j < 2; ++j)
    if (p_.bearing[static_cast<size_t>(j)].housing.mass_kg > 0.0) hidx[static_cast<size_t>(j)] = dim++;
  Eigen::MatrixXcd a = Eigen::MatrixXcd::Zero(dim, dim);
  Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(dim);
  for (int k = 0; k < n; ++k) {
    const double wk = omega_[static_cast<size_t>(k)];
    a(k, k) = cd(wk * wk - w * w, 2.0 * zeta_[static_cast<size_t>(k)] * wk * w);
  }
  const auto& c = p_.controller;
  for (int j = 0; j < 2; ++j) {
    const auto& b = p_.bearing[static_cast<size_t>(j)];
    const cd lag = 1.0 / (1.0 + s * b.actuator_lag_s);
    cd kappa, g(0.0, 0.0);
    if (j == p_.excited) {
      kappa = -b.ks_n_per_m;
      g = b.ki_n_per_a * lag;
    } else {
      cd pid = c.kp_n_per_m + c.ki_n_per_m_s / s;
      const double wf = 2.0 * M_PI * c.derivative_filter_hz;
      pid += c.derivative_filter_hz > 0.0 ? c.kd_n_s_per_m * s / (1.0 + s / wf) : c.kd_n_s_per_m * s;
      kappa = -b.ks_n_per_m + lag * pid * std::exp(-s * p_.loop_delay_s);
    }
    const Eigen::RowVectorXd& row = bearing_row_[static_cast<size_t>(j)];
    a.topLeftCorner(n, n) += kappa * (row.transpose() * row).cast<cd>();
    rhs.head(n) += g * row.transpose().cast<cd>();
    const int h = hidx[static_cast<size_t>(j)];
    if (h >= 0) {
      const auto& hm = b.housing;
      const double wh = 2.0 * M_PI * hm.frequency_hz;
      a.block(0, h, n, 1) -= kappa * row.transpose().cast<cd>();
      a.block(h, 0, 1, n) -= kappa * row.cast<cd>();
      a(h, h) = hm.mass_kg * cd(wh * wh - w * w, 2.0 * hm.damping_ratio * wh * w) + kappa;
      rhs(h) = -g;
    }
  }
  const Eigen::VectorXcd y = a.partialPivLu().solve(rhs);
  return y.head(n);
}

Eigen::RowVectorXd HalfOpenFrf::shape_row(double axial_m) const {
  return rotor::planar_interpolation(model_, axial_m) * phi_;
}

std::vector<std::complex<double>> HalfOpenFrf::accel_per_current(double f_hz, const std::vector<double>& axial_m) const {
  const Eigen::VectorXcd q = modal_response(f_hz);
  const double w = 2.0 * M_PI * f_hz;
  std::vector<cd> out;
  out.reserve(axial_m.size());
  for (double z : axial_m) out.push_back(-w * w * (shape_row(z).cast<cd>() * q)(0));
  return out;
}

}  // namespace amb::model::analysis
