// amb-plant's bench nodes honour the board's loop delay (issue 38): demand frames 1, 2, 3, 4 A
// (one per period) integrated by a plant that integrates its demand; with a delay of d periods
// the integral is the closed form of the held pieces. And the round trip (sample sent ->
// demand received) is measured.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "firmware/board/board.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "hal/sim/sim_rig.hpp"
#include "host-tools/amb-plant/bench_nodes.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;

namespace {

class IntegratorPlant final : public model::Plant {
 public:
  void reset(bool, double) override { x_ = 0.0; }
  void step(double dt_s, const model::PlantInputs& in) override { x_ += dt_s * in.current_demand_a[0]; }
  model::PlantOutputs outputs() const override { return {}; }
  model::PlantTruth truth() const override { return {}; }
  void set_faults(const model::PlantFaults&) override {}
  double x() const { return x_; }

 private:
  double x_ = 0.0;
};

TEST(BenchDelay, DemandFramesActAfterTheBoardsDelay) {
  board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/arm-virt-hil.toml");
  const double t = 1.0 / b.rate_hz;
  for (double d : {0.0, 0.5, 1.0, 1.25}) {
    b.loop_delay_periods = d;
    IntegratorPlant plant;
    hal::sim::LoopbackCanBus board_end, node_end;
    hal::sim::LoopbackCanBus::connect(board_end, node_end);
    plant::BenchNodes nodes(plant, b, node_end);
    const uint8_t amp = b.comms.can.amplifier_node_id;
    for (int k = 0; k < 4; ++k) {
      hal::CanFrame f = fieldbus::encode_demand(amp, {k + 1.0, 0.0, 0.0, 0.0});
      nodes.on_frame(f, k * 1'000'000 + 250'000);
    }
    double expect = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double from = (k + d) * t, to = std::min(4.0 * t, (k + 1 + d) * t);
      if (to > from) expect += (k + 1.0) * (to - from);
    }
    std::printf("[ RESULT ] amb-plant delay %.2f periods: integral %.6e (closed form %.6e); round trips %llu, p50 %.0f us\n",
                d, plant.x(), expect, static_cast<unsigned long long>(nodes.counters().round_trips),
                nodes.counters().round_trip_quantile_ns(0.5) * 1e-3);
    EXPECT_NEAR(plant.x(), expect, 1e-9 * expect + 1e-15) << d;
    // Samples answered at k ms, next demand at k+1 ms + 0: the round trip is 1 ms each time.
    EXPECT_EQ(nodes.counters().round_trips, 3u);
    EXPECT_EQ(nodes.counters().max_round_trip_ns, 1'000'000);
  }
}

}  // namespace
