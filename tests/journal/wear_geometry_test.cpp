// Wear geometry of seed 002 eq. 5-13.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "model/journal/wear_geometry.hpp"

using namespace amb::model::journal;

namespace {
constexpr double k_deg = M_PI / 180.0;
constexpr double k_rb = 67.38e-3 / 2.0, k_c = 185e-6;
}  // namespace

TEST(WearGeometry, TwoParameterDepthSpanAndPosition) {
  // Seed 002 Table 2 wear 1: d0 = 46.5 um, gamma = 23 deg.
  const WearShape w({WearModel::two_parameter, 46.5e-6, 23.0 * k_deg, 0.0}, k_rb, k_c);
  const double centre = 1.5 * M_PI + 23.0 * k_deg;
  EXPECT_NEAR(w.extra_film_m(centre), 46.5e-6, 1e-12);
  // Eq. 6: span from cos(theta - pi/2) = d0/C - 1.
  const double span = 2.0 * (M_PI - std::acos(46.5e-6 / k_c - 1.0));
  EXPECT_NEAR(w.span_rad(), span, 1e-12);
  EXPECT_NEAR(w.span_rad() / k_deg, 83.0, 0.5);  // wear 1 was machined close to this (beta 77 deg)
  EXPECT_NEAR(w.extra_film_m(centre + 0.5 * span - 1e-9), 0.0, 1e-12);
  EXPECT_EQ(w.extra_film_m(centre + 0.5 * span + 1e-3), 0.0);
  EXPECT_EQ(w.extra_film_m(centre + M_PI), 0.0);
  // Eq. 5 inside the span.
  EXPECT_NEAR(w.extra_film_m(centre + 0.2), 46.5e-6 - k_c * (1.0 - std::cos(0.2)), 1e-15);
}

TEST(WearGeometry, EllipticalMatchesEq8To13) {
  // Seed 002 Table 2 wear 2: d0 = 98.28 um, gamma = 5.1 deg, beta = 74 deg.
  const double d0 = 98.28e-6, beta = 74.0 * k_deg;
  const WearShape w({WearModel::elliptical, d0, 5.1 * k_deg, beta}, k_rb, k_c);
  const double centre = 1.5 * M_PI + 5.1 * k_deg;
  EXPECT_NEAR(w.extra_film_m(centre), d0, 1e-12);
  EXPECT_NEAR(w.span_rad(), beta, 1e-15);
  // Edges at theta_s = 3 pi/2 - beta/2 + gamma and theta_f = theta_s + beta.
  const auto e = w.edges_rad();
  EXPECT_NEAR(e[0], 1.5 * M_PI - 0.5 * beta + 5.1 * k_deg, 1e-12);
  EXPECT_NEAR(e[1], 1.5 * M_PI + 0.5 * beta + 5.1 * k_deg, 1e-12);
  EXPECT_NEAR(w.extra_film_m(e[0] + 1e-9), 0.0, 1e-12);
  EXPECT_EQ(w.extra_film_m(e[1] + 1e-6), 0.0);
  // The a of seed 002 (written with theta_s measured from the ellipse's own axis): the
  // canonical point at psi satisfies (y/a)^2 + (z/b)^2 = 1 and the depth decreases monotonically.
  double last = 1.0;
  for (double psi = 0.0; psi < 0.5 * beta; psi += 0.01) {
    const double d = w.extra_film_m(centre + psi);
    EXPECT_LE(d, last + 1e-15);
    EXPECT_NEAR(d, w.extra_film_m(centre - psi), 1e-15);  // symmetric about the maximum
    last = d;
  }
  // A different span changes the film at the same depth (the 3p model's extra freedom).
  const WearShape wide({WearModel::elliptical, d0, 5.1 * k_deg, 124.0 * k_deg}, k_rb, k_c);
  EXPECT_GT(wide.extra_film_m(centre + 30.0 * k_deg), w.extra_film_m(centre + 30.0 * k_deg) + 1e-6);
}

TEST(WearGeometry, RefusesOutOfDomain) {
  EXPECT_THROW(WearShape({WearModel::two_parameter, 2.0 * k_c, 0.0, 0.0}, k_rb, k_c), std::invalid_argument);
  EXPECT_THROW(WearShape({WearModel::elliptical, 50e-6, 0.0, 0.0}, k_rb, k_c), std::invalid_argument);
  EXPECT_THROW(WearShape({WearModel::elliptical, 50e-6, 0.0, M_PI}, k_rb, k_c), std::invalid_argument);
  EXPECT_THROW(WearShape({WearModel::elliptical, -1e-6, 0.0, 1.0}, k_rb, k_c), std::invalid_argument);
  EXPECT_THROW(WearShape({WearModel::elliptical, 5e-3, 0.0, 0.2}, k_rb, k_c), std::invalid_argument);
  const WearShape none({WearModel::none, 0.0, 0.0, 0.0}, k_rb, k_c);
  EXPECT_EQ(none.extra_film_m(1.5 * M_PI), 0.0);
}
