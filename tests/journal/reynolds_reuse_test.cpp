// Speed of the Reynolds solver without changing its result (issue 33): a factorisation reused
// when an active-set iteration's matrix is the latest factorised one (velocity steps of the
// coefficients), the velocity steps taken first from the linearisation point's active set,
// the solver's state restored instead of solved again, and one solver moved from wear to wear
// (set_wear, warm start). The reference is the plain solver (reuse_factorisation = false, a
// new solver per wear): the coefficients must be the same bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "model/journal/reynolds_fvm.hpp"

using namespace amb::model::journal;

namespace {
constexpr double k_deg = M_PI / 180.0;
// The seed-002 rig's bearing (boards/unicamp-journal-rig.toml): R, L, C, mu.
const BearingGeometry k_bearing{0.03369, 0.038, 185e-6, 0.0278};
constexpr double k_spin = 2.0 * M_PI * 34.0;

std::vector<WearParams> wear_scan() {
  std::vector<WearParams> w;
  w.push_back({});  // unworn
  // A path like an optimiser's (small steps), then jumps between seed 002's Table 2 wears.
  for (int k = 0; k < 4; ++k)
    w.push_back({WearModel::elliptical, (46.5 + 0.9 * k) * 1e-6, (23.0 + 0.3 * k) * k_deg, (77.0 - 0.7 * k) * k_deg});
  w.push_back({WearModel::elliptical, 98.5e-6, 5.1 * k_deg, 74.0 * k_deg});
  w.push_back({WearModel::elliptical, 15.0e-6, 19.0 * k_deg, 102.0 * k_deg});
  w.push_back({WearModel::elliptical, 140.0e-6, -40.0 * k_deg, 145.0 * k_deg});
  return w;
}

void expect_same(const DynamicCoefficients& a, const DynamicCoefficients& b) {
  EXPECT_EQ(a.fx0_n, b.fx0_n);
  EXPECT_EQ(a.fy0_n, b.fy0_n);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      EXPECT_EQ(a.stiffness_n_per_m(i, j), b.stiffness_n_per_m(i, j)) << "K" << i << j;
      EXPECT_EQ(a.damping_n_s_per_m(i, j), b.damping_n_s_per_m(i, j)) << "C" << i << j;
    }
}
}  // namespace

TEST(ReynoldsReuse, CoefficientsAreThePlainSolversBitForBit) {
  // 72 x 11: the full width (no mid-plane symmetry with an odd number of axial cells).
  for (const std::array<int, 2> grid : {std::array<int, 2>{72, 12}, std::array<int, 2>{144, 24}, std::array<int, 2>{72, 11}})
    for (const double eps : {0.1, 0.4, 0.7}) {
      SCOPED_TRACE("grid " + std::to_string(grid[0]) + " x " + std::to_string(grid[1]) + ", e " + std::to_string(eps));
      const JournalState s{0.0, -eps * k_bearing.clearance_m, 0.0, 0.0};
      ReynoldsOptions plain;
      plain.cells_theta = grid[0];
      plain.cells_axial = grid[1];
      plain.reuse_factorisation = false;
      ReynoldsOptions fast = plain;
      fast.reuse_factorisation = true;
      const std::vector<WearParams> wears = wear_scan();
      ReynoldsSolver moved(k_bearing, wears.front(), fast);
      long plain_factorisations = 0;
      for (size_t k = 0; k < wears.size(); ++k) {
        SCOPED_TRACE("wear " + std::to_string(k));
        ReynoldsSolver ref(k_bearing, wears[k], plain);
        const DynamicCoefficients a = perturbation_coefficients(ref, s, k_spin);
        plain_factorisations += ref.counters().factorisations;
        moved.set_wear(wears[k]);
        const DynamicCoefficients b = perturbation_coefficients(moved, s, k_spin);
        expect_same(a, b);
        // Both leave the solver at the linearisation point.
        EXPECT_EQ((ref.pressure_pa() - moved.pressure_pa()).cwiseAbs().maxCoeff(), 0.0);
        // And the next solve (another state) is the same too.
        const JournalState t{0.05 * k_bearing.clearance_m, -0.9 * eps * k_bearing.clearance_m, 0.0, 0.0};
        EXPECT_EQ(ref.solve(t, k_spin).fx_n, moved.solve(t, k_spin).fx_n);
      }
      // The point of it: fewer factorisations (printed for docs/journal-bearing.md). Measured
      // 0.50-0.72 of the plain count here; without the sweeps' guess 0.82-0.92.
      std::printf("grid %d x %d, e %.1f: %ld factorisations plain, %ld reused (%ld active-set iterations)\n", grid[0],
                  grid[1], eps, plain_factorisations, moved.counters().factorisations, moved.counters().iterations);
      EXPECT_LE(static_cast<double>(moved.counters().factorisations), 0.75 * static_cast<double>(plain_factorisations));
    }
}

TEST(ReynoldsReuse, AVelocityStepFromTheConvergedSetDoesNotFactorise) {
  ReynoldsOptions o;
  o.cells_theta = 72;
  o.cells_axial = 12;
  ReynoldsSolver s(k_bearing, {WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg}, o);
  const JournalState p{0.0, -0.4 * k_bearing.clearance_m, 0.0, 0.0};
  s.solve(p, k_spin);
  const long f0 = s.counters().factorisations;
  s.solve(p, k_spin);  // the same point again: its active set and matrix are the latest ones
  EXPECT_EQ(s.counters().factorisations, f0);
  JournalState v = p;
  v.vx_m_s = 1e-9 * k_spin * k_bearing.clearance_m;  // a velocity step too small to move the free boundary
  const FilmForces a = s.solve(v, k_spin);
  EXPECT_EQ(s.counters().factorisations, f0);
  ReynoldsOptions plain = o;
  plain.reuse_factorisation = false;
  ReynoldsSolver ref(k_bearing, {WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg}, plain);
  EXPECT_EQ(ref.solve(v, k_spin).fx_n, a.fx_n);
  // A position step changes the matrix: factorised.
  JournalState q = p;
  q.x_m += 1e-9;
  s.solve(q, k_spin);
  EXPECT_GT(s.counters().factorisations, f0);
}

TEST(ReynoldsReuse, AnotherWearIsNotSolvedWithTheLastWearsFactorisation) {
  // The same position and (for a tiny change of wear) the same active set: only the wear tells
  // the two matrices apart.
  ReynoldsOptions o;
  o.cells_theta = 72;
  o.cells_axial = 12;
  const WearParams w1{WearModel::elliptical, 46.5e-6, 23.0 * k_deg, 77.0 * k_deg};
  const WearParams w2{WearModel::elliptical, 46.6e-6, 23.0 * k_deg, 77.0 * k_deg};
  const JournalState p{0.0, -0.4 * k_bearing.clearance_m, 0.0, 0.0};
  ReynoldsSolver moved(k_bearing, w1, o);
  moved.solve(p, k_spin);
  moved.set_wear(w2);
  const FilmForces a = moved.solve(p, k_spin);
  o.reuse_factorisation = false;
  ReynoldsSolver ref(k_bearing, w2, o);
  const FilmForces b = ref.solve(p, k_spin);
  EXPECT_EQ(a.fx_n, b.fx_n);
  EXPECT_EQ(a.fy_n, b.fy_n);
}
