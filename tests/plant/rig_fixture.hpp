#pragma once
// Rig parameters for the plant tests: the two board files through the lead's loader, and
// small hand-built rotors with closed-form answers.
#include <string>

#include "firmware/board/board.hpp"
#include "model/plant/plant_params.hpp"
#include "tests/support/test_paths.hpp"

namespace amb::test {

inline board::BoardConfig board_from_repo(const std::string& name) {
  return board::load_board(std::string(amb::test::source_dir()) + "/boards/" + name + ".toml");
}

/// A uniform solid steel beam of `n` equal elements, no disks.
inline model::RotorParams uniform_beam(double length_m, double diameter_m, int n, double e_pa = 2.1e11,
                                       double rho = 7800.0, double nu = 0.3) {
  model::RotorParams r;
  model::BeamElement el;
  el.length_m = length_m / n;
  el.outer_diameter_m = diameter_m;
  el.inner_diameter_m = 0.0;
  el.density_kg_m3 = rho;
  el.youngs_modulus_pa = e_pa;
  el.poisson_ratio = nu;
  el.structural = true;
  for (int i = 0; i < n; ++i) r.elements.push_back(el);
  return r;
}

}  // namespace amb::test
