// Friction from the contact forces across the plant's friction and speed range (issue 13):
// drops of the project's penalty plant (flexible FE rotor, Kelvin-Voigt contact, regularised
// Coulomb friction against each ring's spin DOF, sensor noise on), amplifiers cut at the first
// sample, 0.3 s at 10 kHz, read by host-tools/core/fit/friction_estimate.
//  * FrictionSweep.Grid (default set, ~3 s: no model fit, the estimate reads the record):
//    friction 0.05-0.5 x 1000-6000 rpm, prints the table of docs/drop-model.md. Command:
//      build/tests/drop/friction_sweep_tests --gtest_filter=FrictionSweep.Grid
//  * FrictionSweepCorners.WithinThreePercent (friction_estimate_test.cpp, default set): eight cells.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/drop/friction_sweep_cell.hpp"

using amb::test::sweep_cell;
using amb::test::SweepCell;

// Every cell: an estimate (none declined), within 3 % of the plant's friction (issue 13's
// "within 3 % everywhere"; 33 of 36 before the bending correction and the clear-window rule of
// session 10), and its uncertainty covers the truth (2 sigma).
TEST(FrictionSweep, Grid) {
  const double mus[] = {0.05, 0.1, 0.2, 0.3, 0.4, 0.5};
  const double rpms[] = {1000, 2000, 3000, 4000, 5000, 6000};
  std::printf("| mu \\ rpm |");
  for (double r : rpms) std::printf(" %.0f |", r);
  std::printf("\n| --- |");
  for (size_t i = 0; i < std::size(rpms); ++i) std::printf(" --- |");
  std::printf("\n");
  int within = 0, declined = 0, total = 0;
  for (double mu : mus) {
    std::printf("| %.2f |", mu);
    for (double rpm : rpms) {
      const SweepCell c = sweep_cell(mu, rpm);
      ++total;
      if (!c.valid) {
        ++declined;
        std::printf(" declined (%d) |", c.used);
        ADD_FAILURE() << "declined: mu " << mu << " rpm " << rpm;
        continue;
      }
      if (std::abs(c.error) <= 0.03) ++within;
      std::printf(" %.4f +- %.4f (%+.1f %%) |", c.estimate, c.uncertainty, 100.0 * c.error);
      EXPECT_LE(std::abs(c.error), 0.03) << "mu " << mu << " rpm " << rpm;
      EXPECT_LE(std::abs(c.estimate - mu), 2.0 * c.uncertainty) << "mu " << mu << " rpm " << rpm;
    }
    std::printf("\n");
  }
  std::printf("%d of %d cells within 3 %%, %d declined\n", within, total, declined);
}
