// The three rubbing regimes of seed 000 (swinging, forward rub, backward whirl) appear for
// parameters that should produce them (classification of the true aux-plane orbit).
#include <cstdio>

#include <gtest/gtest.h>

#include "model/drop/rubbing_states.hpp"
#include "tests/drop/drop_test_util.hpp"

namespace md = amb::model::drop;

namespace {

md::RubbingDurations drop_regime(double unbalance_kg_m, double mu, double ring_inertia_kg_m2) {
  auto p = amb::test::bath_board().plant;
  for (auto& a : p.aux) a.ring_inertia_kg_m2 = ring_inertia_kg_m2;
  for (auto& d : p.rotor.disks) d.unbalance_kg_m = unbalance_kg_m;
  auto m = amb::test::make_drop_model(p);
  m->set_friction_coefficient(mu);
  md::DropScenario sc;
  sc.window_s = 0.5;
  const auto tr = md::simulate_drop(*m, sc, false);
  std::vector<double> x, y;
  for (size_t i = static_cast<size_t>(tr.trigger_index); i < tr.samples.size(); ++i) {
    x.push_back(tr.samples[i].aux_x_m[0]);
    y.push_back(tr.samples[i].aux_y_m[0]);
  }
  const auto d = md::classify_rubbing(x, y, tr.sample_period_s, p.aux[0].clearance_m, 1.0, 0, {}).durations;
  std::printf("unbalance %.0e kg m, mu %.2f, ring %.0e kg m^2: swing %.3f forward %.3f backward %.3f s\n", unbalance_kg_m, mu,
              ring_inertia_kg_m2, d.swing_s, d.forward_s, d.backward_s);
  return d;
}

}  // namespace

TEST(DropRegimes, SwingingForSmallUnbalanceAndLowFriction) {
  // The board's rotor (2e-6 kg m): the rotor bounces and swings at the bottom.
  const auto d = drop_regime(2e-6, 0.05, 2e-5);
  EXPECT_GT(d.swing_s, 0.45);
  EXPECT_LT(d.forward_s + d.backward_s, 0.01);
}

TEST(DropRegimes, ForwardRubForLargeUnbalanceLowFrictionLightRing) {
  // Unbalance force ~ 32 N per disk at 2700 rpm (~ the weight) drives a synchronous
  // forward whirl; a light ring spins up so friction cannot reverse it.
  const auto d = drop_regime(4e-4, 0.05, 2e-5);
  EXPECT_GT(d.forward_s, 0.1);
  EXPECT_LT(d.backward_s, 0.02);
}

TEST(DropRegimes, BackwardWhirlForHighFrictionHeavyRing) {
  // High friction against a ring that cannot follow the collar (100 x the board's
  // inertia): the friction force drives the rotor round against the spin (dry whirl).
  const auto d = drop_regime(1e-4, 0.4, 2e-3);
  EXPECT_GT(d.backward_s, 0.3);
  EXPECT_LT(d.forward_s, 0.05);
}
