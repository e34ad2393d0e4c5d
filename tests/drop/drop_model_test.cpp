// The drop model: contact solver laws, energy, step-size and modal convergence.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "model/drop/contact_solver.hpp"
#include "model/drop/rubbing_states.hpp"
#include "tests/drop/drop_test_util.hpp"

namespace md = amb::model::drop;

namespace {

// One contact (index 0) with unit Delassus; contact 1 and the drags inactive/free.
md::ContactProblem single(double pre_n, double free_n, double pre_t, double free_t, double mu, double e) {
  md::ContactProblem p;
  p.delassus = md::LocalMat::Identity();
  p.free_velocity = md::LocalVec::Zero();
  p.pre_velocity = md::LocalVec::Zero();
  p.pre_velocity(0) = pre_n;
  p.free_velocity(0) = free_n;
  p.pre_velocity(1) = pre_t;
  p.free_velocity(1) = free_t;
  p.active = {true, false};
  p.friction_coefficient = {mu, mu};
  p.restitution = e;
  return p;
}

// Rotor centre at aux plane 0 after the trigger, per sample.
std::vector<std::array<double, 2>> orbit0(const md::DropTrace& tr) {
  std::vector<std::array<double, 2>> o;
  for (size_t i = static_cast<size_t>(tr.trigger_index); i < tr.samples.size(); ++i)
    o.push_back({tr.samples[i].aux_x_m[0], tr.samples[i].aux_y_m[0]});
  return o;
}

double max_distance(const std::vector<std::array<double, 2>>& a, const std::vector<std::array<double, 2>>& b, size_t n) {
  double d = 0.0;
  for (size_t i = 0; i < n && i < a.size() && i < b.size(); ++i) d = std::max(d, std::hypot(a[i][0] - b[i][0], a[i][1] - b[i][1]));
  return d;
}

md::RubbingDurations durations0(const md::DropTrace& tr, double clearance) {
  std::vector<double> x, y;
  for (const auto& p : orbit0(tr)) {
    x.push_back(p[0]);
    y.push_back(p[1]);
  }
  return md::classify_rubbing(x, y, tr.sample_period_s, clearance, 1.0, 0, {}).durations;
}

}  // namespace

TEST(ContactSolver, NewtonImpactLaw) {
  for (double e : {0.0, 0.3, 1.0}) {
    const auto s = md::solve_contacts(single(-0.2, -0.2, 0.0, 0.0, 0.0, e), {}, md::LocalVec::Zero());
    ASSERT_TRUE(s.converged);
    EXPECT_NEAR(s.post_velocity(0), 0.2 * e, 1e-12) << "e " << e;
    EXPECT_GE(s.impulse(0), 0.0);
  }
  // Separating contact: no impulse.
  const auto s = md::solve_contacts(single(0.1, 0.1, 0.0, 0.0, 0.3, 0.3), {}, md::LocalVec::Zero());
  EXPECT_EQ(s.impulse(0), 0.0);
}

TEST(ContactSolver, CoulombStickAndSlip) {
  // Impact stops the normal approach (N = 0.2 with e = 0); slip 0.05 -> stick needs
  // |T| = 2 * 0.05 (average-slip law) = 0.1 <= mu N for mu = 1: sticks; mu = 0.1: slides at mu N.
  auto stick = md::solve_contacts(single(-0.2, -0.2, 0.05, 0.05, 1.0, 0.0), {}, md::LocalVec::Zero());
  EXPECT_NEAR(0.5 * (stick.post_velocity(1) + 0.05), 0.0, 1e-9);
  auto slip = md::solve_contacts(single(-0.2, -0.2, 0.05, 0.05, 0.1, 0.0), {}, md::LocalVec::Zero());
  EXPECT_NEAR(slip.impulse(1), -0.1 * slip.impulse(0), 1e-12);
  EXPECT_GT(slip.post_velocity(1), 0.0);
}

TEST(DropModel, ContactSolverNeverCreatesEnergy) {
  // AMBs off after the trigger. Ledger identity E + D - W - P = E0 at every sample (W: work
  // of unbalance; P: position projection), and every step's impulses dissipate (>= 0).
  struct Case {
    double unbalance_kg_m, mu;
  };
  for (const Case c : {Case{2e-6, 0.15}, Case{4e-4, 0.05}}) {
    auto p = amb::test::bath_board().plant;
    for (auto& d : p.rotor.disks) d.unbalance_kg_m = c.unbalance_kg_m;
    md::DropOptions rigid;
    rigid.contact_law = md::ContactLawChoice::rigid;  // this test is about the rigid law's solver
    auto m = amb::test::make_drop_model(p, rigid);
    m->set_friction_coefficient(c.mu);
    md::DropScenario sc;
    md::levitate(*m, sc);
    amb::model::PlantInputs in;
    in.amplifiers_enabled = false;
    auto balance = [&] {
      const auto& l = m->energy_ledger();
      return m->mechanical_energy_j() + l.dissipated_total_j() - l.external_work_j - l.projection_energy_j;
    };
    const double e0 = balance();
    double worst = 0.0;
    for (int i = 0; i < 3000; ++i) {
      m->step(1e-4, in);
      worst = std::max(worst, std::abs(balance() - e0));
    }
    const auto& l = m->energy_ledger();
    std::printf("unbalance %.0e mu %.2f: E0 %.4f J, worst |balance drift| %.3e J, min step impulse dissipation %.3e J, "
                "dissipated: impact %.4f friction %.4f drag %.4f damping %.2e J, projection %.2e J, unbalance work %.4f J\n",
                c.unbalance_kg_m, c.mu, e0, worst, l.min_step_contact_dissipation_j, l.impact_dissipated_j, l.friction_dissipated_j,
                l.ring_drag_dissipated_j, l.damping_dissipated_j, l.projection_energy_j, l.external_work_j);
    EXPECT_LT(worst, 1e-9 * std::max(1.0, e0));
    EXPECT_GE(l.min_step_contact_dissipation_j, -1e-12);
    EXPECT_GT(l.friction_dissipated_j, 0.0);
    EXPECT_LT(std::abs(l.projection_energy_j), 0.1 * l.dissipated_total_j());
  }
}

TEST(DropModel, ConvergesWithStepSize) {
  // Same levitated state for every h (levitated once, then restored). Order 1: halving h
  // about halves the orbit error over the fall and the first impacts (15 ms) against
  // h = 1.25 us. Rubbing durations over 0.4 s: swinging drop (board rotor) within 2 % of the
  // window per halving; a forward-rub drop is chaotic after ~50 ms, its durations are only
  // asked to stay within 15 % (printed).
  md::DropScenario sc;
  sc.window_s = 0.4;
  sc.pre_trigger_s = 0.0;
  auto run = [&](const amb::model::PlantParams& p, double mu, double h, bool full) {
    md::DropOptions o;
    o.contact_law = md::ContactLawChoice::rigid;  // the rigid Moreau-Jean law (the board says hertz)
    o.sensor_noise = false;
    auto lev = amb::test::make_drop_model(p, o);
    md::levitate(*lev, sc);
    o.step_s = h;
    auto m = amb::test::make_drop_model(p, o);
    m->set_friction_coefficient(mu);
    m->restore(lev->state());
    md::DropScenario s2 = sc;
    if (!full) s2.window_s = 0.015;
    return md::record_drop(*m, s2, false);
  };
  auto p = amb::test::bath_board().plant;
  const auto ref = orbit0(run(p, 0.15, 1.25e-6, false));
  // RMS orbit error over the 15 ms; the impact falls at a random phase of a step, so single
  // halvings scatter: the order is the least-squares slope of log(error) over log(h).
  const std::vector<double> hs{4e-5, 2e-5, 1e-5, 5e-6};
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  double err_20us = 0.0;
  for (double h : hs) {
    const auto o = orbit0(run(p, 0.15, h, false));
    double sum = 0.0;
    const size_t n = std::min<size_t>(150, std::min(o.size(), ref.size()));
    for (size_t i = 0; i < n; ++i) sum += std::pow(std::hypot(o[i][0] - ref[i][0], o[i][1] - ref[i][1]), 2);
    const double e = std::sqrt(sum / static_cast<double>(n));
    if (h == 2e-5) err_20us = e;
    std::printf("h %.1e s: RMS orbit error over 15 ms %.3e m\n", h, e);
    sx += std::log(h);
    sy += std::log(e);
    sxx += std::log(h) * std::log(h);
    sxy += std::log(h) * std::log(e);
  }
  const double np = static_cast<double>(hs.size());
  const double order = (np * sxy - sx * sy) / (np * sxx - sx * sx);
  std::printf("observed order %.2f\n", order);
  EXPECT_GT(order, 0.6);
  EXPECT_LT(order, 2.0);
  EXPECT_LT(err_20us, 0.01 * p.aux[0].clearance_m);

  auto p_fw = p;
  for (auto& d : p_fw.rotor.disks) d.unbalance_kg_m = 4e-4;
  for (int regime = 0; regime < 2; ++regime) {
    std::vector<md::RubbingDurations> dur;
    for (double h : {4e-5, 2e-5, 1e-5}) {
      dur.push_back(durations0(run(regime == 0 ? p : p_fw, regime == 0 ? 0.15 : 0.05, h, true), p.aux[0].clearance_m));
      std::printf("%s h %.1e s: swing %.4f fw %.4f bw %.4f s\n", regime == 0 ? "swinging" : "forward ", h, dur.back().swing_s,
                  dur.back().forward_s, dur.back().backward_s);
    }
    const double tol = (regime == 0 ? 0.02 : 0.15) * sc.window_s;
    for (size_t k = 1; k < dur.size(); ++k) {
      EXPECT_LT(std::abs(dur[k].swing_s - dur[k - 1].swing_s), tol);
      EXPECT_LT(std::abs(dur[k].forward_s - dur[k - 1].forward_s), tol);
      EXPECT_LT(std::abs(dur[k].backward_s - dur[k - 1].backward_s), tol);
    }
  }
}

TEST(DropModel, ConvergesWithModeCount) {
  // Orbit over the first 30 ms for increasing lateral mode counts against 20 modes.
  auto p = amb::test::bath_board().plant;
  md::DropScenario sc;
  sc.window_s = 0.03;
  sc.pre_trigger_s = 0.0;
  auto run = [&](int modes) {
    md::DropOptions o;
    o.contact_law = md::ContactLawChoice::rigid;  // the rigid Moreau-Jean law (the board says hertz)
    o.modes_per_plane = modes;
    o.sensor_noise = false;
    auto m = amb::test::make_drop_model(p, o);
    return orbit0(md::simulate_drop(*m, sc, false));
  };
  const auto ref = run(20);
  double prev = 1e9;
  for (int modes : {4, 8, 12}) {
    const double e = max_distance(run(modes), ref, 300);
    std::printf("modes %d: max orbit difference to 20 modes over 30 ms %.3e m\n", modes, e);
    EXPECT_LT(e, prev * 1.01);
    prev = e;
  }
  EXPECT_LT(prev, 0.02 * p.aux[0].clearance_m);  // the board's 12 modes: within 2 % of the clearance
}

TEST(DropModel, ServesAsPlantWithoutAllocation) {
  md::DropOptions o;
  o.contact_law = md::ContactLawChoice::rigid;  // the rigid Moreau-Jean law (the board says hertz)
  o.internal_controller = false;
  auto m = amb::test::make_drop_model(amb::test::bath_board().plant, o);
  m->reset(false, 10.0);
  amb::model::PlantInputs in;
  in.amplifiers_enabled = false;
  Eigen::internal::set_is_malloc_allowed(false);
  for (int i = 0; i < 100; ++i) m->step(1e-4, in);
  Eigen::internal::set_is_malloc_allowed(true);
  const auto t = m->truth();
  // On the ring (radius = clearance to 1 um) near its bottom (spin friction walks it sideways a little).
  EXPECT_NEAR(std::hypot(t.aux_x_m[0], t.aux_y_m[0]), amb::test::bath_board().plant.aux[0].clearance_m, 1e-6);
  EXPECT_LT(t.aux_y_m[0], -0.95 * amb::test::bath_board().plant.aux[0].clearance_m);
  EXPECT_NEAR(m->outputs().t_s, 0.01, 1e-12);
}
