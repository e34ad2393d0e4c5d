// The finite-volume Reynolds film against Raimondi & Boyd's finite-bearing tables, grid
// converged (Richardson extrapolation from two grids, the order checked).
//
// Source of the numbers: A. A. Raimondi and J. Boyd, "A solution for the finite journal
// bearing and its application to analysis and design", ASLE Transactions 1 (1958), Parts
// I-III; the full (360 deg) bearing table as reproduced in Shigley's Mechanical Engineering
// Design (Table 12-4 in the 9th/10th editions): Sommerfeld number S = (R/C)^2 mu N / P
// (N rev/s, P = W / (L D)) and attitude angle phi (deg) over the eccentricity ratio
// e = 1 - h0/C, for L/D = 1, 1/2 and 1/4. The table prints S to 3 significant digits and
// phi to 0.01 deg (4 digits; 3 at L/D 1, e = 0.1): its rounding is < 0.2 % in S and < 0.07 %
// in phi, far inside 1 %, so the comparison is at 1 % with no allowance for the printing.
//
// Raimondi & Boyd's problem: p = 0 at the bearing ends, the full film starting at the
// maximum film thickness (p = 0 there) and the Reynolds (Swift-Stieber) condition at its
// end. The solver is run with that inlet (ReynoldsOptions::zero_pressure_at_max_film);
// the production setting (the complementarity problem alone places the start of the film)
// differs from it at light load only (docs/journal-bearing.md, "Film against Raimondi &
// Boyd"), and is checked here against the same table with its own, measured margin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "model/journal/reynolds_fvm.hpp"
#include "tests/journal/fd_film.hpp"

using namespace amb::model::journal;

namespace {
constexpr double k_mu = 0.03, k_r = 0.03, k_c = 60e-6, k_omega = 2.0 * M_PI * 30.0;

struct TableRow {
  double l_over_d, eps, sommerfeld, phi_deg;
};
// Raimondi & Boyd (1958) / Shigley Table 12-4, full bearing.
constexpr TableRow k_rows[] = {
    {1.0, 0.1, 1.33, 79.5},    {1.0, 0.2, 0.631, 74.02},  {1.0, 0.4, 0.264, 63.10},
    {1.0, 0.6, 0.121, 50.58},  {1.0, 0.8, 0.0446, 36.24}, {1.0, 0.9, 0.0188, 26.45},
    {0.5, 0.1, 4.31, 81.62},   {0.5, 0.2, 2.03, 74.94},   {0.5, 0.4, 0.779, 61.45},
    {0.5, 0.6, 0.319, 48.14},  {0.5, 0.8, 0.0923, 33.31}, {0.5, 0.9, 0.0313, 23.66},
    {0.25, 0.1, 16.2, 82.31},  {0.25, 0.2, 7.57, 75.18},  {0.25, 0.4, 2.83, 60.86},
    {0.25, 0.6, 1.07, 46.72},  {0.25, 0.8, 0.261, 31.04}, {0.25, 0.9, 0.0736, 21.85},
};

struct Performance {
  double sommerfeld, phi_deg;
};

// S and phi of the bearing at eccentricity eps on an nt x nz grid. The journal is displaced
// so that the maximum film falls on the centre of cell nt/4 (R & B's inlet line is then a
// row of cells); S and phi do not depend on the direction.
Performance performance(double l_over_d, double eps, int nt, int nz, bool rb_inlet) {
  const BearingGeometry g{k_r, l_over_d * 2.0 * k_r, k_c, k_mu};
  ReynoldsOptions o;
  o.cells_theta = nt;
  o.cells_axial = nz;
  o.zero_pressure_at_max_film = rb_inlet;
  ReynoldsSolver s(g, {}, o);
  const double tm = s.theta_rad(nt / 4), e = eps * k_c;
  const FilmForces f = s.solve({-e * std::cos(tm), -e * std::sin(tm), 0.0, 0.0}, k_omega);
  EXPECT_TRUE(f.converged);
  // Rotate into the frame where the journal sits straight down: load line +y.
  const double a = M_PI / 2 - tm;
  const double fx = std::cos(a) * f.fx_n - std::sin(a) * f.fy_n, fy = std::sin(a) * f.fx_n + std::cos(a) * f.fy_n;
  const double w = std::hypot(fx, fy);
  const double sommerfeld = k_mu * (k_omega / (2.0 * M_PI)) * (2.0 * k_r * g.length_m / w) * (k_r / k_c) * (k_r / k_c);
  return {sommerfeld, std::atan2(fx, fy) * 180.0 / M_PI};
}

// The same with the independent finite-difference film (tests/journal/fd_film.hpp: nodes,
// the film sampled at half nodes, projected SOR) and R & B's inlet as p = 0 on the node of the
// maximum film; nt x nz nodes / axial intervals.
Performance fd_performance(double l_over_d, double eps, int nt, int nz) {
  const BearingGeometry g{k_r, l_over_d * 2.0 * k_r, k_c, k_mu};
  amb::test::journal::FdFilm film(g, {}, nt, nz);
  const int i_max = nt / 4;
  film.set_zero_pressure_node(i_max);
  const double tm = 2.0 * M_PI * i_max / nt, e = eps * k_c;
  const auto f = film.force_n({-e * std::cos(tm), -e * std::sin(tm), 0.0, 0.0}, k_omega);
  const double a = M_PI / 2 - tm;
  const double fx = std::cos(a) * f[0] - std::sin(a) * f[1], fy = std::sin(a) * f[0] + std::cos(a) * f[1];
  const double w = std::hypot(fx, fy);
  const double sommerfeld = k_mu * (k_omega / (2.0 * M_PI)) * (2.0 * k_r * g.length_m / w) * (k_r / k_c) * (k_r / k_c);
  return {sommerfeld, std::atan2(fx, fy) * 180.0 / M_PI};
}

// Richardson extrapolation of a second-order quantity from grids h and h/2.
double richardson(double coarse, double fine) { return fine + (fine - coarse) / 3.0; }

// The table values the solver misses by more than 1 % (named, not met): the attitude at
// L/D 1/2, e = 0.8 (32.93 deg against 33.31, -1.14 %) and the Sommerfeld number at L/D 1,
// e = 0.4 (0.2604 against 0.264, -1.37 %). Two independent discretisations (this solver and
// the finite-difference film) agree there to 0.002 deg and 0.01 %, grid-converged, and the
// table's printing (3 digits in S, 0.01 deg in phi) accounts for < 0.2 % / 0.02 %: what is left
// is the difference between this Reynolds problem and R & B's 1958 numbers
// (docs/journal-bearing.md, "Film against Raimondi & Boyd").
struct Miss {
  double l_over_d, eps;
  bool sommerfeld;  // true: S misses, false: phi misses
};
constexpr Miss k_misses[] = {{0.5, 0.8, false}, {1.0, 0.4, true}};

bool named_miss(const TableRow& row, bool sommerfeld) {
  for (const Miss& m : k_misses)
    if (m.l_over_d == row.l_over_d && m.eps == row.eps && m.sommerfeld == sommerfeld) return true;
  return false;
}
}  // namespace

TEST(RaimondiBoyd, FiniteBearingWithinOnePercentGridConverged) {
  int met = 0, total = 0;
  for (const TableRow& row : k_rows) {
    const Performance p1 = performance(row.l_over_d, row.eps, 60, 10, true);
    const Performance p2 = performance(row.l_over_d, row.eps, 120, 20, true);
    const Performance p3 = performance(row.l_over_d, row.eps, 240, 40, true);
    // Grid convergence: the change of S shrinks with refinement (second order: ~4x; the
    // free boundary makes it irregular at some points, so > 2x is asserted), and the
    // Richardson estimate of the remaining error of the 240 x 40 grid is below 0.2 %.
    const double d12 = std::abs(p2.sommerfeld - p1.sommerfeld), d23 = std::abs(p3.sommerfeld - p2.sommerfeld);
    EXPECT_GT(d12 / d23, 2.0) << "L/D " << row.l_over_d << " e " << row.eps;
    EXPECT_LT(d23 / 3.0 / p3.sommerfeld, 2e-3) << "L/D " << row.l_over_d << " e " << row.eps;
    const double s = richardson(p2.sommerfeld, p3.sommerfeld), phi = richardson(p2.phi_deg, p3.phi_deg);
    // The independent finite-difference film, same inlet, same extrapolation.
    const Performance q2 = fd_performance(row.l_over_d, row.eps, 120, 20);
    const Performance q3 = fd_performance(row.l_over_d, row.eps, 240, 40);
    const double sf = richardson(q2.sommerfeld, q3.sommerfeld), phif = richardson(q2.phi_deg, q3.phi_deg);
    std::printf("L/D %.2f e %.1f: S %.5g (table %.4g, %+.2f %%) phi %.3f deg (table %.2f, %+.2f %%); FD film S %.5g phi %.3f\n",
                row.l_over_d, row.eps, s, row.sommerfeld, 100.0 * (s / row.sommerfeld - 1.0), phi, row.phi_deg,
                100.0 * (phi / row.phi_deg - 1.0), sf, phif);
    EXPECT_NEAR(sf / s, 1.0, 5e-4) << "L/D " << row.l_over_d << " e " << row.eps << ": the two films disagree";
    EXPECT_NEAR(phif, phi, 0.02) << "L/D " << row.l_over_d << " e " << row.eps << ": the two films disagree";
    for (const bool is_s : {true, false}) {
      const double err = is_s ? s / row.sommerfeld - 1.0 : phi / row.phi_deg - 1.0;
      ++total;
      if (named_miss(row, is_s)) {
        // Kept honest both ways: a named miss that starts to pass must leave the list (and the docs).
        EXPECT_GT(std::abs(err), 0.01) << "L/D " << row.l_over_d << " e " << row.eps << " is no longer a miss";
      } else {
        EXPECT_LT(std::abs(err), 0.01) << "L/D " << row.l_over_d << " e " << row.eps << (is_s ? " S" : " phi");
        met += std::abs(err) < 0.01 ? 1 : 0;
      }
    }
  }
  std::printf("%d of %d values within 1 %% of the table\n", met, total);
}

TEST(RaimondiBoyd, ProductionCavitationDiffersOnlyWhereTheFilmStarts) {
  // The default film (complementarity alone) on the same 240 x 40 grid: the load agrees with
  // the table as closely (within 1.1 %, measured max +1.0 % at L/D 1/2, e = 0.4), the attitude
  // is larger at light load, where the free start of the film moves upstream of the maximum
  // film: measured +1.45 deg at L/D 1/2, e = 0.1, < 0.5 deg from e = 0.6 on.
  // L/D 1/2 and 1/4 (the bearing's 38 mm / 67 mm = 0.56 lies there). At L/D 1 the free start
  // moves further upstream: S -2.1 / -1.2 / -1.5 % and phi +4.4 / +3.8 / +2.6 deg over R & B's
  // inlet at e = 0.1 / 0.2 / 0.4, +1.4 / +0.6 deg at 0.6 / 0.8 (docs/journal-bearing.md).
  for (const TableRow& row : k_rows) {
    if (row.l_over_d > 0.5) continue;
    const Performance rb = performance(row.l_over_d, row.eps, 240, 40, true);
    const Performance lcp = performance(row.l_over_d, row.eps, 240, 40, false);
    EXPECT_NEAR(lcp.sommerfeld / row.sommerfeld, 1.0, 0.011) << "L/D " << row.l_over_d << " e " << row.eps;
    EXPECT_GE(lcp.phi_deg, rb.phi_deg - 0.1) << "L/D " << row.l_over_d << " e " << row.eps;
    EXPECT_LT(lcp.phi_deg - rb.phi_deg, row.eps < 0.5 ? 1.6 : 0.5) << "L/D " << row.l_over_d << " e " << row.eps;
  }
}
