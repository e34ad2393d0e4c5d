#include "model/rotor/rotor_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/timoshenko_element.hpp"

namespace amb::model::rotor {
namespace {

// The structural element whose section forms the core under sleeve `i`.
int core_element(const std::vector<BeamElement>& els, int i) {
  for (int j = i - 1; j >= 0; --j)
    if (els[static_cast<size_t>(j)].structural) return j;
  for (size_t j = static_cast<size_t>(i) + 1; j < els.size(); ++j)
    if (els[j].structural) return static_cast<int>(j);
  return -1;
}

}  // namespace

RotorModel build_rotor_model(const RotorParams& p) {
  detail::count_fe_build();
  const auto& els = p.elements;
  if (els.empty()) throw std::invalid_argument("rotor: no elements");
  RotorModel m;
  m.node_count = static_cast<int>(els.size()) + 1;
  const int n2 = 2 * m.node_count;
  m.node_axial_m.assign(static_cast<size_t>(m.node_count), 0.0);
  m.planar_mass = Eigen::MatrixXd::Zero(n2, n2);
  m.planar_stiffness = Eigen::MatrixXd::Zero(n2, n2);
  m.planar_polar = Eigen::MatrixXd::Zero(n2, n2);

  for (size_t i = 0; i < els.size(); ++i) {
    const BeamElement& e = els[i];
    if (!(e.length_m > 0.0) || !(e.outer_diameter_m > 0.0) || e.inner_diameter_m >= e.outer_diameter_m)
      throw std::invalid_argument("rotor: element " + std::to_string(i) + " has a non-positive size");
    m.node_axial_m[i + 1] = m.node_axial_m[i] + e.length_m;
    ElementMatrices em;
    double phi = 0.0;
    if (e.structural) {
      phi = element_section(e).phi;
      em = element_matrices(e, phi, true);
    } else {
      const int c = core_element(els, static_cast<int>(i));
      if (c < 0) throw std::invalid_argument("rotor: no structural element to carry sleeve " + std::to_string(i));
      BeamElement core = els[static_cast<size_t>(c)];
      core.length_m = e.length_m;
      if (core.outer_diameter_m > e.inner_diameter_m + 1e-9)
        throw std::invalid_argument("rotor: sleeve " + std::to_string(i) + " bore smaller than its core");
      phi = element_section(core).phi;
      em = element_matrices(core, phi, true);
      const ElementMatrices sleeve = element_matrices(e, phi, false);
      em.mass += sleeve.mass;
      em.polar += sleeve.polar;
    }
    m.element_phi.push_back(phi);
    const int o = 2 * static_cast<int>(i);
    m.planar_mass.block<4, 4>(o, o) += em.mass;
    m.planar_stiffness.block<4, 4>(o, o) += em.stiffness;
    m.planar_polar.block<4, 4>(o, o) += em.polar;
    const ElementSection s = element_section(e);
    m.polar_inertia_kg_m2 += e.density_kg_m3 * 2.0 * s.second_moment_m4 * e.length_m;
    if (!e.structural) {
      BeamElement core = els[static_cast<size_t>(core_element(els, static_cast<int>(i)))];
      m.polar_inertia_kg_m2 += core.density_kg_m3 * 2.0 * element_section(core).second_moment_m4 * e.length_m;
    }
  }
  m.length_m = m.node_axial_m.back();

  for (size_t d = 0; d < p.disks.size(); ++d) {
    const RigidDisk& disk = p.disks[d];
    const int n = node_index(m, disk.axial_m);
    if (n < 0) throw std::invalid_argument("rotor: disk " + std::to_string(d) + " is not on a node");
    m.planar_mass(2 * n, 2 * n) += disk.mass_kg;
    m.planar_mass(2 * n + 1, 2 * n + 1) += disk.transverse_inertia_kg_m2;
    m.planar_polar(2 * n + 1, 2 * n + 1) += disk.polar_inertia_kg_m2;
    m.polar_inertia_kg_m2 += disk.polar_inertia_kg_m2;
  }

  // Rigid-body vectors give mass, centre of mass and transverse inertia exactly from the
  // consistent mass matrix (translation: w = 1; rotation about z = 0: w = z, b = 1).
  Eigen::VectorXd t = Eigen::VectorXd::Zero(n2), r = Eigen::VectorXd::Zero(n2);
  for (int n = 0; n < m.node_count; ++n) {
    t(2 * n) = 1.0;
    r(2 * n) = m.node_axial_m[static_cast<size_t>(n)];
    r(2 * n + 1) = 1.0;
  }
  m.mass_kg = t.dot(m.planar_mass * t);
  m.centre_of_mass_m = t.dot(m.planar_mass * r) / m.mass_kg;
  m.transverse_inertia_kg_m2 = r.dot(m.planar_mass * r) - m.mass_kg * m.centre_of_mass_m * m.centre_of_mass_m;

  m.M = Eigen::MatrixXd::Zero(2 * n2, 2 * n2);
  m.K = Eigen::MatrixXd::Zero(2 * n2, 2 * n2);
  m.G = Eigen::MatrixXd::Zero(2 * n2, 2 * n2);
  m.M.topLeftCorner(n2, n2) = m.planar_mass;
  m.M.bottomRightCorner(n2, n2) = m.planar_mass;
  m.K.topLeftCorner(n2, n2) = m.planar_stiffness;
  m.K.bottomRightCorner(n2, n2) = m.planar_stiffness;
  // Spin about +z: I_t bx'' + I_p Omega by' = Q_bx, I_t by'' - I_p Omega bx' = Q_by.
  m.G.topRightCorner(n2, n2) = m.planar_polar;
  m.G.bottomLeftCorner(n2, n2) = -m.planar_polar;
  m.C = p.rayleigh_alpha_1_per_s * m.M + p.rayleigh_beta_s * m.K;
  return m;
}

Eigen::RowVectorXd planar_interpolation(const RotorModel& m, double axial_m) {
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(2 * m.node_count);
  const double z = std::min(std::max(axial_m, 0.0), m.length_m);
  int e = 0;
  while (e < m.node_count - 2 && z > m.node_axial_m[static_cast<size_t>(e) + 1]) ++e;
  const double z0 = m.node_axial_m[static_cast<size_t>(e)];
  const double l = m.node_axial_m[static_cast<size_t>(e) + 1] - z0;
  row.segment<4>(2 * e) = displacement_shape((z - z0) / l, l, m.element_phi[static_cast<size_t>(e)]);
  return row;
}

int node_index(const RotorModel& m, double axial_m, double tol_m) {
  for (int n = 0; n < m.node_count; ++n)
    if (std::abs(m.node_axial_m[static_cast<size_t>(n)] - axial_m) <= tol_m) return n;
  return -1;
}

}  // namespace amb::model::rotor
