#include "model/rig/rig_model.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace amb::model {
namespace {

std::string differ(const std::string& what, double a, double b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s %.6g vs %.6g", what.c_str(), a, b);
  return buf;
}

}  // namespace

RigModel::RigModel(const PlantParams& p) : p_(p) {
  fe_ = rotor::build_rotor_model(p.rotor);
  basis_ = rotor::modal_basis(fe_, p.rotor);
  board_ = reduction(p.rotor.modes_kept);
  for (size_t b = 0; b < 2; ++b) {
    law_[b] = magnet::make_axis_law(p.amb[b]);
    lin_[b] = magnet::linearise(law_[b], 0.0, 0.0);
  }
}

Eigen::RowVectorXd RigModel::modal_row(const RigReduction& r, double axial_m) const {
  return rotor::modal_interpolation(fe_, r.reduced, axial_m);
}

RigReduction RigModel::reduction(int modes_per_plane) const {
  RigReduction r;
  r.reduced = rotor::truncate_basis(basis_, fe_, modes_per_plane);
  r.gravity_y_n = rotor::modal_gravity_load(fe_, r.reduced, p_.gravity_m_s2);
  for (size_t b = 0; b < 2; ++b) {
    r.amb[b] = modal_row(r, p_.amb[b].axial_m);
    r.aux[b] = modal_row(r, p_.aux[b].axial_m);
  }
  for (size_t s = 0; s < 4; ++s) r.sensor[s] = modal_row(r, p_.sensor[s].axial_m);
  r.coupling = modal_row(r, fe_.length_m);
  r.mid_span = modal_row(r, 0.5 * fe_.length_m);
  double best = 1e300;
  for (size_t d = 0; d < p_.rotor.disks.size(); ++d) {
    r.disk.push_back(modal_row(r, p_.rotor.disks[d].axial_m));
    const double dist = std::abs(p_.rotor.disks[d].axial_m - 0.5 * fe_.length_m);
    if (dist < best) {
      best = dist;
      r.mid_disk = static_cast<int>(d);
    }
  }
  return r;
}

UnbalanceExpansion unbalance_expansion(const RigReduction& r, const RotorParams& rotor) {
  UnbalanceExpansion u;
  u.sin_sum = Eigen::VectorXd::Zero(r.modes());
  u.cos_sum = Eigen::VectorXd::Zero(r.modes());
  for (size_t d = 0; d < rotor.disks.size() && d < r.disk.size(); ++d) {
    const double ph = rotor.disks[d].unbalance_phase_deg * M_PI / 180.0;
    const Eigen::VectorXd b = r.disk[d].transpose();
    u.sin_sum += rotor.disks[d].unbalance_kg_m * std::sin(ph) * b;
    u.cos_sum += rotor.disks[d].unbalance_kg_m * std::cos(ph) * b;
  }
  if (r.mid_disk >= 0) {
    u.mid_row = r.disk[static_cast<size_t>(r.mid_disk)];
    u.mid_phase_rad = rotor.disks[static_cast<size_t>(r.mid_disk)].unbalance_phase_deg * M_PI / 180.0;
  } else {
    u.mid_row = r.mid_span;
  }
  return u;
}

std::string RigModel::differs_from(const PlantParams& p) const {
  const RotorParams& a = p_.rotor;
  const RotorParams& b = p.rotor;
  if (a.elements.size() != b.elements.size())
    return differ("rotor element count", static_cast<double>(a.elements.size()), static_cast<double>(b.elements.size()));
  for (size_t i = 0; i < a.elements.size(); ++i) {
    const BeamElement& x = a.elements[i];
    const BeamElement& y = b.elements[i];
    const std::string n = "rotor element " + std::to_string(i) + " ";
    if (x.length_m != y.length_m) return differ(n + "length_m", x.length_m, y.length_m);
    if (x.outer_diameter_m != y.outer_diameter_m) return differ(n + "outer_diameter_m", x.outer_diameter_m, y.outer_diameter_m);
    if (x.inner_diameter_m != y.inner_diameter_m) return differ(n + "inner_diameter_m", x.inner_diameter_m, y.inner_diameter_m);
    if (x.density_kg_m3 != y.density_kg_m3) return differ(n + "density_kg_m3", x.density_kg_m3, y.density_kg_m3);
    if (x.youngs_modulus_pa != y.youngs_modulus_pa) return differ(n + "youngs_modulus_pa", x.youngs_modulus_pa, y.youngs_modulus_pa);
    if (x.poisson_ratio != y.poisson_ratio) return differ(n + "poisson_ratio", x.poisson_ratio, y.poisson_ratio);
    if (x.structural != y.structural) return n + "structural differs";
  }
  if (a.disks.size() != b.disks.size())
    return differ("disk count", static_cast<double>(a.disks.size()), static_cast<double>(b.disks.size()));
  for (size_t i = 0; i < a.disks.size(); ++i) {
    const RigidDisk& x = a.disks[i];
    const RigidDisk& y = b.disks[i];
    const std::string n = "disk " + std::to_string(i) + " ";
    if (x.axial_m != y.axial_m) return differ(n + "axial_m", x.axial_m, y.axial_m);
    if (x.mass_kg != y.mass_kg) return differ(n + "mass_kg", x.mass_kg, y.mass_kg);
    if (x.polar_inertia_kg_m2 != y.polar_inertia_kg_m2) return differ(n + "polar_inertia_kg_m2", x.polar_inertia_kg_m2, y.polar_inertia_kg_m2);
    if (x.transverse_inertia_kg_m2 != y.transverse_inertia_kg_m2)
      return differ(n + "transverse_inertia_kg_m2", x.transverse_inertia_kg_m2, y.transverse_inertia_kg_m2);
  }
  if (a.rayleigh_alpha_1_per_s != b.rayleigh_alpha_1_per_s) return differ("rayleigh_alpha_1_per_s", a.rayleigh_alpha_1_per_s, b.rayleigh_alpha_1_per_s);
  if (a.rayleigh_beta_s != b.rayleigh_beta_s) return differ("rayleigh_beta_s", a.rayleigh_beta_s, b.rayleigh_beta_s);
  if (a.modes_kept != b.modes_kept) return differ("modes_kept", a.modes_kept, b.modes_kept);
  for (size_t i = 0; i < 2; ++i) {
    if (p_.amb[i].axial_m != p.amb[i].axial_m) return differ("amb " + std::to_string(i) + " axial_m", p_.amb[i].axial_m, p.amb[i].axial_m);
    if (p_.aux[i].axial_m != p.aux[i].axial_m) return differ("aux bearing " + std::to_string(i) + " axial_m", p_.aux[i].axial_m, p.aux[i].axial_m);
  }
  for (size_t i = 0; i < 4; ++i)
    if (p_.sensor[i].axial_m != p.sensor[i].axial_m) return differ("sensor " + std::to_string(i) + " axial_m", p_.sensor[i].axial_m, p.sensor[i].axial_m);
  if (p_.gravity_m_s2 != p.gravity_m_s2) return differ("gravity_m_s2", p_.gravity_m_s2, p.gravity_m_s2);
  return {};
}

void RigModel::check_same_rig(const PlantParams& p, const char* who) const {
  if (const std::string d = differs_from(p); !d.empty())
    throw std::invalid_argument(std::string(who) + ": the rig model was built for another rotor: " + d);
}

}  // namespace amb::model
