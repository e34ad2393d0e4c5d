// The replay HAL backend on its own: steps to each recorded timestamp, returns the recorded
// inputs, reproduces the discrete flags, records the outputs, and does not allocate per sample.
#define AMB_DEFINE_ALLOC_COUNTER
#include "tests/firmware/alloc_counter.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "hal/replay/replay_rig.hpp"

namespace {
using amb::hal::replay::ReplayRig;
using amb::hal::replay::ReplaySample;

std::vector<ReplaySample> ramp(size_t n) {
  std::vector<ReplaySample> v(n);
  for (size_t i = 0; i < n; ++i) {
    v[i].analog.t_ns = 1'000'000 + static_cast<int64_t>(i) * 100'000;
    v[i].analog.displacement_m = {1e-6 * static_cast<double>(i), 0.0, 0.0, -1e-6};
    v[i].analog.coil_current_a = {0.5, 0.0, 0.0, 0.25 * static_cast<double>(i)};
    v[i].discrete.external_trigger = i == 3;
    v[i].discrete.landing_request = i == 4;
    v[i].discrete.amplifier_fault = i == 5;
  }
  v[2].read_ok = false;
  v[2].analog.t_ns = v[1].analog.t_ns;  // a failed read keeps the last good time
  return v;
}

TEST(ReplayRig, StepsThroughTheRecording) {
  ReplayRig rig;
  rig.configure(ramp(8), 100'000);
  EXPECT_EQ(rig.clock().now_ns(), 900'000);  // one period before the first sample
  amb::hal::AnalogInputs in{};
  for (size_t i = 0; i < 8; ++i) {
    const int64_t t = rig.clock().wait_until_ns(0);  // the deadline does not matter
    const bool ok = rig.analog().read(in);
    const auto din = rig.discrete().read();
    EXPECT_EQ(ok, i != 2) << i;
    if (i != 2) {
      EXPECT_EQ(t, 1'000'000 + static_cast<int64_t>(i) * 100'000);
      EXPECT_EQ(in.displacement_m[0], 1e-6 * static_cast<double>(i));
      EXPECT_EQ(in.coil_current_a[3], 0.25 * static_cast<double>(i));
    } else {
      EXPECT_EQ(in.displacement_m[0], 1e-6);  // untouched: still sample 1's
    }
    EXPECT_EQ(din.external_trigger, i == 3);
    EXPECT_EQ(din.landing_request, i == 4);
    EXPECT_EQ(din.amplifier_fault, i == 5);
    amb::hal::AnalogOutputs out{};
    out.current_demand_a[1] = static_cast<double>(i);
    rig.analog().write(out);
    rig.discrete().write({true, i % 2 == 0, true});
  }
  EXPECT_TRUE(rig.finished());
  for (size_t i = 0; i < 8; ++i) {
    EXPECT_TRUE(rig.outputs()[i].analog_written);
    EXPECT_EQ(rig.outputs()[i].analog.current_demand_a[1], static_cast<double>(i));
    EXPECT_EQ(rig.outputs()[i].discrete.watchdog, i % 2 == 0);
  }
  // Past the end: no sample, counted, never thrown; the clock stays on the last sample.
  EXPECT_EQ(rig.clock().wait_until_ns(0), 1'700'000);
  EXPECT_FALSE(rig.analog().read(in));
  rig.analog().write({});
  EXPECT_EQ(rig.counters().reads_past_end, 1u);
  EXPECT_EQ(rig.counters().writes_past_end, 1u);
  EXPECT_EQ(rig.counters().periods, 8u);
}

TEST(ReplayRig, RefusesBadRecordings) {
  ReplayRig rig;
  EXPECT_THROW(rig.configure({}, 100'000), std::invalid_argument);
  auto v = ramp(4);
  v[3].analog.t_ns = v[2].analog.t_ns - 1;
  try {
    rig.configure(v, 100'000);
    FAIL() << "accepted decreasing times";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 3"), std::string::npos) << e.what();
  }
}

TEST(ReplayRig, ReadWriteDoNotAllocate) {
  ReplayRig rig;
  rig.configure(ramp(1000), 100'000);
  amb::hal::AnalogInputs in{};
  amb::hal::AnalogOutputs out{};
  const long before = amb::test::allocations();
  for (int i = 0; i < 1200; ++i) {  // past the end too
    rig.clock().wait_until_ns(0);
    rig.analog().read(in);
    (void)rig.discrete().read();
    rig.analog().write(out);
    rig.discrete().write({});
    (void)rig.clock().now_ns();
  }
  EXPECT_EQ(amb::test::allocations() - before, 0);
}

}  // namespace
