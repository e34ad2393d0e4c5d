// Exploration / regimes of the drop model.
#include <cstdio>

#include <gtest/gtest.h>

#include "model/drop/rubbing_states.hpp"
#include "model/drop/sensor_orbit.hpp"
#include "tests/drop/drop_test_util.hpp"

namespace md = amb::model::drop;

TEST(DropExplore, Print) {
  for (double unb : {2e-6, 1e-4, 4e-4}) {
  for (double mu : {0.05, 0.4}) {
    for (double jr : {2e-5, 2e-3}) {
    for (double td : {0.02, 0.5}) {
      auto p = amb::test::bath_board().plant;
      p.aux[0].ring_inertia_kg_m2 = p.aux[1].ring_inertia_kg_m2 = jr;
      p.aux[0].ring_friction_torque_n_m = p.aux[1].ring_friction_torque_n_m = td;
      for (auto& d : p.rotor.disks) d.unbalance_kg_m = unb;
      auto m = amb::test::make_drop_model(p);
      m->set_friction_coefficient(mu);
      md::DropScenario sc;
      sc.window_s = 0.5;
      const auto tr = md::simulate_drop(*m, sc);
      std::vector<double> x, y;
      for (size_t i = static_cast<size_t>(tr.trigger_index); i < tr.samples.size(); ++i) {
        x.push_back(tr.samples[i].aux_x_m[0] - p.aux[0].centre_offset_x_m);
        y.push_back(tr.samples[i].aux_y_m[0] - p.aux[0].centre_offset_y_m);
      }
      const auto r = md::classify_rubbing(x, y, tr.sample_period_s, p.aux[0].clearance_m, 1.0, 0, {});
      std::printf("unb %.0e mu %.2f Jr %.0e td %.2f: swing %.3f fw %.3f bw %.3f  spin_end %.1f ring %.1f  pen %.2e unconv %lu sweeps %d fr %.3f imp %.3f proj %.4f\n",
                  unb, mu, jr, td, r.durations.swing_s, r.durations.forward_s, r.durations.backward_s,
                  tr.samples.back().spin_rad_s, tr.samples.back().ring_rad_s[0], tr.counters.max_penetration_m,
                  static_cast<unsigned long>(tr.counters.solver_unconverged), tr.counters.solver_max_sweeps,
                  tr.ledger.friction_dissipated_j, tr.ledger.impact_dissipated_j, tr.ledger.projection_energy_j);
    }}
  }}
}
