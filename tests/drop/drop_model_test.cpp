#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "tests/drop/drop_test_util.hpp"

namespace md = amb::model::drop;

TEST(DropDebug, Levitate) {
  auto p = amb::test::bath_board().plant;
  for (int modes : {2, 3, 4, 6, 12}) {
    md::DropOptions o;
    o.sensor_noise = false;
    o.modes_per_plane = modes;
    std::printf("modes %d\n", modes);
    auto m = amb::test::make_drop_model(p, o);
    m->reset(true, 0.0);
    amb::model::PlantInputs in;
    in.amplifiers_enabled = true;
    for (int i = 0; i < 1000; ++i) {
      m->step(1e-4, in);
      const auto a = m->aux_position_m(0);
      const auto& s = m->state();
      if (i % 200 == 0)
        std::printf("t %.4f x %.3e y %.3e dem %.3f %.3f %.3f %.3f int %.1f %.1f\n", s.t_s, a[0], a[1], s.demand_a[0], s.demand_a[1],
                    s.demand_a[2], s.demand_a[3], s.pid_integral_n[1], s.pid_integral_n[3]);
    }
  }
}
