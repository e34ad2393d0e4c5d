// Lifecycle and safe-state path of the supervisor, driven with synthetic samples, and the
// proof that the control step does not allocate.
#define AMB_DEFINE_ALLOC_COUNTER
#include "tests/firmware/alloc_counter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "model/amb/amb_force.hpp"
#include "model/rotor/rotor_model.hpp"

using namespace amb::fw;

namespace {

class SupervisorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    board = amb::board::load_board("bath-amb-rig");
    sup.configure(board);
    // Rotor resting on the touchdown bearings: 0.3 mm down at both planes.
    set_xy(0.0, -0.3e-3);
  }
  void set_xy(double x, double y) {
    const double a = M_PI / 4;
    for (int b = 0; b < 2; ++b) {
      in.displacement_m[2 * b] = x * std::sin(a) + y * std::cos(a);
      in.displacement_m[2 * b + 1] = -x * std::sin(a) + y * std::cos(a);
    }
  }
  // Perfect position tracking: the rotor is wherever the set-point says (from the status).
  /// Levitate, settle at the centre, then read an orbit beyond lifecycle.max_orbit_fault_m for
  /// one step (the orbit_limit fault path).
  void levitate_then_exceed_orbit_limit() {
    sup.post(Command::levitate);
    steps(1);
    set_xy(0.0, 0.0);
    steps(static_cast<int>((board.lifecycle.liftoff_ramp_s + board.lifecycle.settle_s) * board.rate_hz) + 10);
    set_xy(0.0, -1.2 * board.lifecycle.max_orbit_fault_m);
    steps(1);
  }
  void steps(int n, bool follow = true, bool ok = true) {
    for (int i = 0; i < n; ++i) {
      in.t_ns += 100000;
      sup.step(in, ok, din, out, dout);
      if (follow) {
        const Status s = sup.status();
        (void)s;
      }
    }
  }
  amb::board::BoardConfig board;
  Supervisor sup;
  amb::hal::AnalogInputs in{};
  amb::hal::DiscreteInputs din{};
  amb::hal::AnalogOutputs out{};
  amb::hal::DiscreteOutputs dout{};
};

}  // namespace

TEST_F(SupervisorTest, ConfiguredBoardIsInactiveWithAmplifiersOff) {
  steps(10);
  EXPECT_EQ(sup.state(), State::inactive);
  EXPECT_FALSE(out.amplifiers_enabled);
  EXPECT_FALSE(dout.amplifier_enable);
  for (double i : out.current_demand_a) EXPECT_EQ(i, 0.0);
}

TEST_F(SupervisorTest, LiftOffRampsTheSetPointFromTouchdownToCentre) {
  ASSERT_TRUE(sup.post(Command::levitate));
  steps(1);
  EXPECT_EQ(sup.state(), State::levitating);
  EXPECT_EQ(sup.status().phase, Phase::lifting);
  EXPECT_TRUE(out.amplifiers_enabled);
  // Pretend the rotor follows; after the ramp and the settle time it is levitated.
  set_xy(0.0, 0.0);
  steps(static_cast<int>((board.lifecycle.liftoff_ramp_s + board.lifecycle.settle_s) * board.rate_hz) + 10);
  EXPECT_EQ(sup.status().phase, Phase::levitated);
}

TEST_F(SupervisorTest, RunIsRefusedUntilLevitatedAndCounted) {
  ASSERT_TRUE(sup.post(Command::run));
  steps(1);
  EXPECT_EQ(sup.state(), State::inactive);
  EXPECT_EQ(sup.status().counters.rejected_commands, 1u);
}

TEST_F(SupervisorTest, SpinUpLandAndSwitchOff) {
  sup.post(Command::levitate);
  steps(1);
  set_xy(0.0, 0.0);
  steps(static_cast<int>((board.lifecycle.liftoff_ramp_s + board.lifecycle.settle_s) * board.rate_hz) + 10);
  ASSERT_TRUE(sup.post(Command::run));
  steps(1);
  EXPECT_EQ(sup.state(), State::running);
  const double t_up = board.lifecycle.operating_speed_hz / board.lifecycle.spin_accel_hz_per_s;
  steps(static_cast<int>(t_up * board.rate_hz) + 10);
  EXPECT_EQ(sup.status().phase, Phase::at_speed);
  EXPECT_NEAR(out.spin_speed_command_hz, board.lifecycle.operating_speed_hz, 1e-9);
  ASSERT_TRUE(sup.post(Command::land));
  steps(static_cast<int>(t_up * board.rate_hz) + 10);
  EXPECT_EQ(sup.status().phase, Phase::lowering);
  EXPECT_EQ(out.spin_speed_command_hz, 0.0);
  steps(static_cast<int>(board.lifecycle.landing_ramp_s * board.rate_hz) + 10);
  EXPECT_EQ(sup.state(), State::inactive);
  EXPECT_FALSE(out.amplifiers_enabled);
}

TEST_F(SupervisorTest, OrbitBeyondLimitEntersSafeState) {
  levitate_then_exceed_orbit_limit();
  EXPECT_EQ(sup.state(), State::fault);
  EXPECT_EQ(sup.status().fault, FaultReason::orbit_limit);
  EXPECT_FALSE(out.amplifiers_enabled);
  EXPECT_FALSE(dout.status_ok);
  EXPECT_EQ(sup.status().counters.safe_state_entries, 1u);
  // The watchdog stops toggling in the safe state.
  const bool w = dout.watchdog;
  steps(3);
  EXPECT_EQ(dout.watchdog, w);
  // Only an explicit reset leaves the fault.
  sup.post(Command::levitate);
  steps(1);
  EXPECT_EQ(sup.state(), State::fault);
  sup.post(Command::reset_fault);
  steps(1);
  EXPECT_EQ(sup.state(), State::inactive);
}

TEST_F(SupervisorTest, AmplifierFaultInputEntersSafeState) {
  sup.post(Command::levitate);
  steps(5);
  din.amplifier_fault = true;
  steps(1);
  EXPECT_EQ(sup.status().fault, FaultReason::amplifier_fault);
}

TEST_F(SupervisorTest, MissingSamplesAreCountedThenFatal) {
  sup.post(Command::levitate);
  steps(5);
  steps(5, true, false);
  EXPECT_EQ(sup.state(), State::levitating);
  EXPECT_EQ(sup.status().counters.read_failures, 5u);
  steps(10, true, false);
  EXPECT_EQ(sup.status().fault, FaultReason::sensor_invalid);
}

TEST_F(SupervisorTest, EmergencyStopFromAnyActiveState) {
  sup.post(Command::levitate);
  steps(5);
  sup.post(Command::emergency_stop);
  steps(1);
  EXPECT_EQ(sup.status().fault, FaultReason::emergency_stop);
}

TEST_F(SupervisorTest, ControlStepDoesNotAllocate) {
  sup.post(Command::levitate);
  steps(10);
  const long before = amb::test::allocations();
  steps(20000);  // lifting, settling, commands, notches: 2 s of loop
  sup.post(Command::run);
  steps(20000);
  EXPECT_EQ(amb::test::allocations() - before, 0);
  // The counter works (otherwise this test could not fail).
  auto* p = new int(3);
  EXPECT_EQ(amb::test::allocations() - before, 1);
  delete p;
}

TEST_F(SupervisorTest, LiftOffStartsWithTheWeightPreloaded) {
  // At the levitate command the error is zero, so the first demand is the integrators'
  // preload on top of the set-point feed-forward (the current at which the bias flux pulls
  // with zero force where the rotor rests, 0.3 mm below centre): through the board's force
  // law at that position the demand lifts the weight (the law's ki there is ki0 g0^2 /
  // (g0^2 - z^2), a little above the board's), and the feed-forward alone lifts nothing.
  ASSERT_TRUE(sup.post(Command::levitate));
  steps(1);
  double lift_n = 0.0, ff_lift_n = 0.0, pull_n = 0.0;
  for (size_t b = 0; b < 2; ++b) {
    const auto law = amb::model::magnet::make_axis_law(board.plant.amb[b]);
    for (size_t a = 0; a < 2; ++a) {
      const auto u = amb::model::magnet::axis_direction(board.plant.amb[b].actuator_angle_deg[a]);
      const double z = u[1] * -0.3e-3;
      const double ff = amb::model::magnet::zero_force_current_a(law, z);
      lift_n += u[1] * amb::model::magnet::axis_force_n(law, z, out.current_demand_a[2 * b + a]);
      ff_lift_n += u[1] * amb::model::magnet::axis_force_n(law, z, ff);
      pull_n += u[1] * amb::model::magnet::axis_force_n(law, z, 0.0);
    }
  }
  const double weight_n = amb::model::rotor::build_rotor_model(board.plant.rotor).mass_kg * board.plant.gravity_m_s2;
  std::printf("[ RESULT ] first demand lifts %.1f N (weight %.1f N); feed-forward alone %.2g N; bias pull without it %.0f N\n",
              lift_n, weight_n, ff_lift_n, pull_n);
  EXPECT_NEAR(lift_n, weight_n, 0.1 * weight_n);
  EXPECT_NEAR(ff_lift_n, 0.0, 1e-6 * weight_n);
  EXPECT_LT(pull_n, -weight_n);  // what the feed-forward removes: more than the weight, downwards
}

// reset() leaves the supervisor as configure() does: after a lift-off, a fault and a posted
// command, reset() and then the same inputs give the same outputs, step by step, as a freshly
// configured supervisor (PID states, counters, set-points, pending command all cleared).
TEST_F(SupervisorTest, ResetBehavesLikeAFreshConfigure) {
  levitate_then_exceed_orbit_limit();
  ASSERT_EQ(sup.state(), State::fault);
  sup.post(Command::run);  // left pending
  sup.reset();
  Supervisor fresh;
  fresh.configure(board);
  EXPECT_EQ(sup.state(), State::inactive);
  EXPECT_EQ(sup.status().counters.safe_state_entries, 0u);
  amb::hal::AnalogOutputs out_fresh{};
  amb::hal::DiscreteOutputs dout_fresh{};
  set_xy(0.0, -0.3e-3);
  ASSERT_TRUE(sup.post(Command::levitate));
  ASSERT_TRUE(fresh.post(Command::levitate));
  for (int i = 0; i < 3000; ++i) {
    in.t_ns += 100000;
    if (i == 100) set_xy(1e-5, -0.25e-3);
    sup.step(in, true, din, out, dout);
    fresh.step(in, true, din, out_fresh, dout_fresh);
    for (size_t k = 0; k < 4; ++k) ASSERT_EQ(out.current_demand_a[k], out_fresh.current_demand_a[k]) << "step " << i;
    ASSERT_EQ(sup.status().phase, fresh.status().phase) << "step " << i;
  }
}
