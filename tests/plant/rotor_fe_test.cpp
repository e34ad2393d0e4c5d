// Rotor finite elements against closed-form beam results, gyroscopic whirl splitting, mass
// bookkeeping and the convergence of the modal reduction.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"
#include "tests/plant/rig_fixture.hpp"

namespace amb::model::rotor {
namespace {

constexpr double k_e = 2.1e11, k_rho = 7800.0;

double eb_scale(double l, double d) {
  const double a = M_PI * d * d / 4.0, i = M_PI * std::pow(d, 4) / 64.0;
  return std::sqrt(k_e * i / (k_rho * a * std::pow(l, 4)));
}

// Slender (L/d = 250) free-free beam: the flexible modes after the two rigid-body modes
// follow (beta_n L)^2 sqrt(EI / (rho A L^4)), beta_n L = 4.7300, 7.8532, 10.9956, 14.1372.
TEST(RotorFe, FreeFreeSlenderBeamMatchesEulerBernoulli) {
  const double l = 1.0, d = 0.004;
  const RotorParams p = test::uniform_beam(l, d, 40);
  const RotorModel m = build_rotor_model(p);
  const std::vector<double> f = free_free_frequencies_rad_s(m);
  const double bl[4] = {4.730041, 7.853205, 10.995608, 14.137165};
  EXPECT_LT(f[0], 1e-3 * f[2]);
  EXPECT_LT(f[1], 1e-3 * f[2]);
  for (int n = 0; n < 4; ++n) {
    const double exact = bl[n] * bl[n] * eb_scale(l, d);
    const double err = f[static_cast<size_t>(n) + 2] / exact - 1.0;
    std::printf("[ RESULT ] free-free mode %d: exact %.2f rad/s, FE %.2f, err %.4f %%\n", n + 1, exact,
                f[static_cast<size_t>(n) + 2], 100.0 * err);
    EXPECT_LT(std::abs(err), 1e-3) << n;
  }
}

// Pinned-pinned (stiff springs at both ends, rotation free): (n pi)^2 sqrt(EI / (rho A L^4)).
TEST(RotorFe, PinnedPinnedSlenderBeamMatchesEulerBernoulli) {
  const double l = 1.0, d = 0.004;
  const RotorParams p = test::uniform_beam(l, d, 40);
  const RotorModel m = build_rotor_model(p);
  const double k = 1e6 * k_e * M_PI * std::pow(d, 4) / 64.0 / std::pow(l, 3);
  const std::vector<double> f = supported_frequencies_rad_s(m, {{0.0, k}, {l, k}});
  for (int n = 1; n <= 3; ++n) {
    const double exact = std::pow(n * M_PI, 2) * eb_scale(l, d);
    const double err = f[static_cast<size_t>(n) - 1] / exact - 1.0;
    std::printf("[ RESULT ] pinned-pinned mode %d: exact %.2f rad/s, FE %.2f, err %.4f %%\n", n, exact,
                f[static_cast<size_t>(n) - 1], 100.0 * err);
    EXPECT_LT(std::abs(err), 2e-3) << n;
  }
}

// Stubby beam (L/d = 3): shear and rotary inertia lower the frequencies well below
// Euler-Bernoulli; the FE matches the exact Timoshenko simply-supported frequency, the lower
// root of (kGA k^2 - rho A w^2)(EI k^2 + kGA - rho I w^2) = (kGA k)^2, k = n pi / L.
TEST(RotorFe, TimoshenkoShearLowersStubbyBeamFrequencies) {
  const double l = 0.15, d = 0.05, nu = 0.3;
  const RotorParams p = test::uniform_beam(l, d, 30, k_e, k_rho, nu);
  const RotorModel m = build_rotor_model(p);
  const double a = M_PI * d * d / 4.0, i = M_PI * std::pow(d, 4) / 64.0;
  const double kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu), g = k_e / (2.0 * (1.0 + nu));
  const double ks = 1e6 * k_e * i / std::pow(l, 3);
  const std::vector<double> f = supported_frequencies_rad_s(m, {{0.0, ks}, {l, ks}});
  for (int n = 1; n <= 2; ++n) {
    const double k = n * M_PI / l, kga = kappa * g * a;
    // Quadratic in w^2: c2 w^4 + c1 w^2 + c0 = 0.
    const double c2 = k_rho * a * k_rho * i;
    const double c1 = -(kga * k * k * k_rho * i + k_rho * a * (k_e * i * k * k + kga));
    const double c0 = kga * k * k * (k_e * i * k * k + kga) - kga * kga * k * k;
    const double w2 = (-c1 - std::sqrt(c1 * c1 - 4.0 * c2 * c0)) / (2.0 * c2);
    const double timo = std::sqrt(w2), eb = std::pow(n * M_PI, 2) * eb_scale(l, d);
    const double fe = f[static_cast<size_t>(n) - 1];
    std::printf("[ RESULT ] stubby L/d=3 mode %d: Euler-Bernoulli %.0f rad/s, Timoshenko exact %.0f, FE %.0f (err %.3f %%, %.1f %% below EB)\n",
                n, eb, timo, fe, 100.0 * (fe / timo - 1.0), 100.0 * (1.0 - fe / eb));
    EXPECT_LT(std::abs(fe / timo - 1.0), 5e-3) << n;
    EXPECT_LT(fe, 0.95 * eb) << n;  // shear matters here
  }
}

// Total mass = sum of element and disk masses; the polar inertia likewise.
TEST(RotorFe, MassIsSumOfElementsAndDisks) {
  RotorParams p = test::uniform_beam(0.6, 0.03, 12);
  p.elements[3].inner_diameter_m = 0.01;
  BeamElement sleeve = p.elements[5];
  sleeve.structural = false;
  sleeve.outer_diameter_m = 0.07;
  sleeve.inner_diameter_m = 0.03;
  p.elements[5] = sleeve;
  p.disks.push_back({0.1, 0.8, 4e-4, 2.5e-4, 0.0, 0.0});
  p.disks.push_back({0.5, 0.3, 1e-4, 6e-5, 0.0, 0.0});
  const RotorModel m = build_rotor_model(p);
  double mass = 0.0, ip = 0.0;
  for (size_t e = 0; e < p.elements.size(); ++e) {
    const auto& el = p.elements[e];
    const double od = el.structural ? el.outer_diameter_m : 0.03;  // core under the sleeve
    const double id = el.structural ? el.inner_diameter_m : 0.0;
    mass += k_rho * M_PI / 4.0 * (od * od - id * id) * el.length_m;
    ip += k_rho * M_PI / 32.0 * (std::pow(od, 4) - std::pow(id, 4)) * el.length_m;
    if (!el.structural) {
      mass += k_rho * M_PI / 4.0 * (0.07 * 0.07 - 0.03 * 0.03) * el.length_m;
      ip += k_rho * M_PI / 32.0 * (std::pow(0.07, 4) - std::pow(0.03, 4)) * el.length_m;
    }
  }
  for (const auto& d : p.disks) {
    mass += d.mass_kg;
    ip += d.polar_inertia_kg_m2;
  }
  EXPECT_NEAR(m.mass_kg, mass, 1e-9 * mass);
  EXPECT_NEAR(m.polar_inertia_kg_m2, ip, 1e-9 * ip);
  // The sleeve stiffens nothing: same stiffness matrix as the plain shaft there.
  RotorParams plain = p;
  plain.elements[5] = p.elements[4];
  EXPECT_LT((build_rotor_model(plain).planar_stiffness - m.planar_stiffness).norm(), 1e-9 * m.planar_stiffness.norm());
}

// Undamped whirl frequencies of the spring-supported spinning rotor in the reduced (modal)
// coordinates the plant uses: [e; v]' = [[0, I], [-(W2 + S), -spin G_r]] per plane pair.
std::vector<double> whirl_frequencies(const RotorModel& m, const RotorParams& p, const std::vector<PointSpring>& springs,
                                      double spin) {
  const ReducedRotor r = reduce_rotor(m, p, 6);
  const Eigen::Index k = r.modes;
  Eigen::MatrixXd s = r.omega2.asDiagonal();
  for (const auto& sp : springs) {
    const Eigen::RowVectorXd b = modal_interpolation(m, r, sp.axial_m);
    s += sp.stiffness_n_per_m * b.transpose() * b;
  }
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(4 * k, 4 * k);
  a.block(0, 2 * k, 2 * k, 2 * k).setIdentity();
  a.block(2 * k, 0, k, k) = -s;
  a.block(3 * k, k, k, k) = -s;
  a.block(2 * k, 3 * k, k, k) = -spin * r.polar;
  a.block(3 * k, 2 * k, k, k) = spin * r.polar;
  Eigen::EigenSolver<Eigen::MatrixXd> es(a, false);
  std::vector<double> f;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
    if (es.eigenvalues()(i).imag() > 0.0) f.push_back(es.eigenvalues()(i).imag());
  std::sort(f.begin(), f.end());
  return f;
}

// A stiff short cylinder on two equal end springs: the conical modes split with speed as
// It w^2 -/+ Ip W w - k_tilt = 0 (forward up, backward down); the bounce mode does not move.
TEST(RotorFe, GyroscopicsSplitsForwardAndBackwardWhirl) {
  const double l = 0.2, d = 0.1;
  const RotorParams p = test::uniform_beam(l, d, 10, 30.0 * k_e);  // bending modes > 100x the rigid ones
  const RotorModel m = build_rotor_model(p);
  const double k = 1e6;
  const double mass = m.mass_kg, ip = mass * d * d / 8.0, it = mass * (l * l / 12.0 + d * d / 16.0);
  const double ktilt = 2.0 * k * (l / 2.0) * (l / 2.0);
  const double bounce = std::sqrt(2.0 * k / mass);
  for (double spin : {0.0, 500.0, 2000.0}) {
    const std::vector<double> f = whirl_frequencies(m, p, {{0.0, k}, {l, k}}, spin);
    const double disc = std::sqrt(ip * ip * spin * spin + 4.0 * it * ktilt);
    const double fw = (ip * spin + disc) / (2.0 * it), bw = (-ip * spin + disc) / (2.0 * it);
    // The lowest four: bounce x2 and the two conical whirls (ordered by value).
    std::vector<double> expect{bounce, bounce, bw, fw};
    std::sort(expect.begin(), expect.end());
    std::printf("[ RESULT ] spin %.0f rad/s: rigid-body whirl FE %.1f %.1f %.1f %.1f rad/s, closed form "
                "(bounce, bounce, backward, forward) %.1f %.1f %.1f %.1f\n", spin, f[0], f[1], f[2], f[3], bounce, bounce, bw, fw);
    for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(f[i], expect[i], 1e-3 * expect[i]) << "spin " << spin << " i " << i;
  }
}

// The reduction converges on a supported rotor: the lowest 6 frequencies of the Bath rotor on
// its AMB net stiffness are within 1 % with the modes_kept of the board file.
TEST(RotorFe, ModalReductionConvergesForBoardRotors) {
  for (const char* name : {"bath-amb-rig", "unicamp-amb-rig"}) {
    const auto board = test::board_from_repo(name);
    const RotorModel m = build_rotor_model(board.plant.rotor);
    const double knet = board.controller.kp_n_per_m - board.plant.amb[0].ks_n_per_m;
    const std::vector<PointSpring> springs{{board.plant.amb[0].axial_m, knet}, {board.plant.amb[1].axial_m, knet}};
    const ModalConvergence c = check_modal_convergence(m, board.plant.rotor, springs, 4, 20, 0.01);
    for (size_t i = 0; i < c.modes.size(); ++i)
      std::printf("[ RESULT ] %s: %d modes/plane -> worst error of the lowest 4 supported frequencies %.3f %%\n", name,
                  c.modes[i], 100.0 * c.max_relative_error[i]);
    ASSERT_GT(c.modes_needed, 0) << name;
    EXPECT_LE(c.modes_needed, board.plant.rotor.modes_kept) << name;
    // More modes never make it worse by more than round-off.
    for (size_t i = 1; i < c.modes.size(); ++i) EXPECT_LE(c.max_relative_error[i], c.max_relative_error[i - 1] + 1e-9);
  }
}

// Interpolation reproduces rigid-body motion exactly at any position.
TEST(RotorFe, InterpolationIsExactForRigidMotion) {
  const RotorParams p = test::uniform_beam(0.6, 0.03, 7);
  const RotorModel m = build_rotor_model(p);
  Eigen::VectorXd q(2 * m.node_count);
  for (int n = 0; n < m.node_count; ++n) {
    q(2 * n) = 1e-3 + 2e-3 * m.node_axial_m[static_cast<size_t>(n)];
    q(2 * n + 1) = 2e-3;
  }
  for (double z : {0.0, 0.013, 0.2, 0.3333, 0.6})
    EXPECT_NEAR(planar_interpolation(m, z).dot(q), 1e-3 + 2e-3 * z, 1e-15) << z;
}

}  // namespace
}  // namespace amb::model::rotor
