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
    require(a.mass_kg >= 0.0 && a.transverse_inertia_kg_m2 >= 0.0, "attached mass and inertia must be >= 0");
    const Eigen::RowVectorXd n = rotor::planar_interpolation(model_, a.axial_m);
    m += a.mass_kg * n.transpose() * n;
    if (a.transverse_inertia_kg_m2 > 0.0) {
      const int node = rotor::node_index(model_, a.axial_m, 1e-6);
      require(node >= 0, "an attached inertia needs a rotor node at its position");
      m(2 * node + 1, 2 * node + 1) += a.transverse_inertia_kg_m2;
    }
  }
  for (const auto& res : p.resonators)
    require(res.mass_kg > 0.0 && res.frequency_hz > 0.0 && res.damping_ratio >= 0.0, "resonator mass and frequency must be > 0");
  for (const auto& g : p.supports)
    require(g.stiffness_n_per_m >= 0.0 && g.damping_n_s_per_m >= 0.0, "support stiffness and damping must be >= 0");
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
    require(b.ki_n_per_a > 0.0 && b.ks_n_per_m >= 0.0 && b.actuator_lag_s >= 0.0 && b.eddy_time_s >= 0.0,
            "bearing constants out of range");
    bearing_row_[static_cast<size_t>(j)] = rotor::planar_interpolation(model_, b.axial_m) * phi_;
  }
}

std::complex<double> HalfOpenFrf::eddy_factor(const HalfOpenBearing& b, double f_hz) {
  if (!(b.eddy_time_s > 0.0)) return 1.0;
  return 1.0 / (1.0 + std::sqrt(cd(0.0, 2.0 * M_PI * f_hz * b.eddy_time_s)));
}

std::complex<double> HalfOpenFrf::controller_force_per_m(double f_hz) const {
  const cd s(0.0, 2.0 * M_PI * f_hz);
  const auto& c = p_.controller;
  cd pid = c.kp_n_per_m + c.ki_n_per_m_s / s;
  const double wf = 2.0 * M_PI * c.derivative_filter_hz;
  pid += c.derivative_filter_hz > 0.0 ? c.kd_n_s_per_m * s / (1.0 + s / wf) : c.kd_n_s_per_m * s;
  return pid * std::exp(-s * p_.loop_delay_s);
}

Eigen::VectorXcd HalfOpenFrf::modal_response(double f_hz) const { return solve(f_hz).head(static_cast<Eigen::Index>(omega_.size())); }

std::complex<double> HalfOpenFrf::sensor_displacement(double f_hz) const {
  const Eigen::VectorXcd y = solve(f_hz);
  const int n = static_cast<int>(omega_.size());
  const size_t e = static_cast<size_t>(p_.excited);
  cd x = (bearing_row_[e].cast<cd>() * y.head(n))(0);
  if (p_.bearing[e].housing.mass_kg > 0.0) {
    int h = n;
    if (e == 1 && p_.bearing[0].housing.mass_kg > 0.0) ++h;
    x -= y(h);
  }
  return x;
}

Eigen::VectorXcd HalfOpenFrf::solve(double f_hz) const {
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
  for (int j = 0; j < 2; ++j) {
    const auto& b = p_.bearing[static_cast<size_t>(j)];
    const cd lag = 1.0 / (1.0 + s * b.actuator_lag_s);
    const cd ec = eddy_factor(b, f_hz);
    cd kappa, g(0.0, 0.0);
    if (j == p_.excited) {
      kappa = -b.ks_n_per_m * ec;
      g = b.ki_n_per_a * ec;
    } else {
      kappa = ec * (-b.ks_n_per_m + lag * controller_force_per_m(f_hz));
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
  // Attached resonators and ground supports: their dynamic stiffness at the attachment point
  // (a resonator condensed: k* (-w^2 m) / (k* - w^2 m), k* = k + i w c).
  auto add_point = [&](double z, cd k) {
    const Eigen::RowVectorXd row = rotor::planar_interpolation(model_, z) * phi_;
    a.topLeftCorner(n, n) += k * (row.transpose() * row).cast<cd>();
  };
  for (const auto& r : p_.resonators) {
    const double wr = 2.0 * M_PI * r.frequency_hz;
    const cd kr(r.mass_kg * wr * wr, 2.0 * r.damping_ratio * r.mass_kg * wr * w);
    const double inertia = -w * w * r.mass_kg;
    add_point(r.axial_m, kr * inertia / (kr + inertia));
  }
  for (const auto& g : p_.supports) add_point(g.axial_m, cd(g.stiffness_n_per_m, g.damping_n_s_per_m * w));
  return a.partialPivLu().solve(rhs);
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
