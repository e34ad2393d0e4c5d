#pragma once
// A second, independent film solver, for the tests only (issue 33): records made with it are
// identified with the production film (model/journal/reynolds_fvm), so the identification is
// not checked on data from its own discretisation (the inverse crime).
//
// What differs from the production solver:
//  - finite differences on NODES (theta_i = i 2 pi / N, axial nodes at both ends with p = 0),
//    not finite volumes on cells;
//  - the film and its slope are SAMPLED at the half nodes (h_{i+-1/2} = h(theta_i +- d/2)),
//    not integrated exactly between centres; the wear's edges are not treated specially;
//  - Reynolds (Swift-Stieber) cavitation by Christopherson's projected SOR (Gauss-Seidel
//    sweeps with p = max(0, p)), not a primal-dual active set with sparse LDLT solves;
//  - the full width (no mid-plane symmetry), dimensional variables, trapezoidal force sums.
// Shared with the production code: only the bearing's description (BearingGeometry, the wear
// shape of seed 002 eq. 5-13) and the result types.
#include <array>
#include <vector>

#include "model/journal/reynolds_fvm.hpp"
#include "model/journal/wear_geometry.hpp"

namespace amb::test::journal {

class FdFilm {
 public:
  /// `nodes_theta` circumferential nodes (>= 12), `intervals_axial` axial intervals (>= 2).
  FdFilm(const model::journal::BearingGeometry& g, const model::journal::WearParams& w, int nodes_theta,
         int intervals_axial);
  /// Film force on the journal (x, y), N. Warm-started from the last pressure field.
  std::array<double, 2> force_n(const model::journal::JournalState& s, double spin_rad_s);
  /// Static force and K, C by central differences (steps relative_step * C, relative_step * C * spin).
  model::journal::DynamicCoefficients coefficients(const model::journal::JournalState& s, double spin_rad_s,
                                                   double relative_step = 1e-2);
  int last_sweeps() const { return sweeps_; }
  /// Raimondi & Boyd's inlet: p = 0 on the circumferential node `i` (all axial nodes), where
  /// the caller places the maximum film; -1 (default): no inlet line, cavitation alone.
  void set_zero_pressure_node(int i) { zero_node_ = i; }

 private:
  model::journal::BearingGeometry g_;
  model::journal::WearShape wear_;
  int nt_, nz_;
  std::vector<double> p_;
  int sweeps_ = 0;
  int zero_node_ = -1;
};

}  // namespace amb::test::journal
