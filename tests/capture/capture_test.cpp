// Floating capture and Phase A triggers: window contents, trigger conditions, debounce,
// hysteresis, one event per incident, re-arm policy, lost events, and no allocation.
#define AMB_DEFINE_ALLOC_COUNTER
#include "tests/firmware/alloc_counter.hpp"

#include <gtest/gtest.h>

#include "firmware/capture/floating_capture.hpp"
#include "tests/capture/synthetic_samples.hpp"

namespace {
using namespace amb::fw;
using amb::test::synthetic_sample;

constexpr double k_rate = 10000.0;
const std::array<double, 4> k_angles{45.0, -45.0, 45.0, -45.0};

CaptureParams small_params() {
  CaptureParams p;
  p.pre_trigger_s = 0.01;   // 100 samples
  p.post_trigger_s = 0.02;  // 200 samples
  p.rearm_hold_s = 0.005;   // 50 samples
  p.event_buffers = 2;
  return p;
}

struct Feeder {
  FloatingCapture& c;
  uint64_t seq = 0;
  void run(uint64_t n, uint32_t flags = 0) {
    for (uint64_t i = 0; i < n; ++i) c.on_sample(synthetic_sample(seq++, flags));
  }
};

TEST(Capture, WindowHoldsPreAndPostAroundTheTrigger) {
  FloatingCapture c;
  c.configure(small_params(), k_angles, k_rate);
  Feeder f{c};
  f.run(1000);
  EXPECT_EQ(c.take(), nullptr);
  ASSERT_TRUE(c.request_manual_trigger());
  const uint64_t trigger_seq = f.seq;
  f.run(199);
  EXPECT_EQ(c.take(), nullptr) << "frozen before the post window was complete";
  f.run(1);
  const FrozenEvent* e = c.take();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->header.cause, TriggerCause::manual);
  EXPECT_EQ(e->header.trigger_index, 100u);
  EXPECT_EQ(e->header.sample_count, 300u);
  EXPECT_EQ(e->header.trigger_seq, trigger_seq);
  for (uint32_t i = 0; i < e->header.sample_count; ++i) {
    EXPECT_EQ(e->samples[i].seq, trigger_seq - 100 + i);
    EXPECT_TRUE(amb::test::is_intact(e->samples[i]));
  }
  c.release(e);
}

TEST(Capture, ShortHistoryAtStartKeepsWhatThereIs) {
  FloatingCapture c;
  c.configure(small_params(), k_angles, k_rate);
  Feeder f{c};
  f.run(30);
  c.request_manual_trigger();
  f.run(200);
  const FrozenEvent* e = c.take();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->header.trigger_index, 30u);
  EXPECT_EQ(e->samples[0].seq, 0u);
  c.release(e);
}

TEST(Capture, PreLongerThanPostIsStillComplete) {
  CaptureParams p = small_params();
  p.pre_trigger_s = 0.05;   // 500
  p.post_trigger_s = 0.003; // 30: 17 pre copies per sample
  FloatingCapture c;
  c.configure(p, k_angles, k_rate);
  Feeder f{c};
  f.run(2000);
  c.request_manual_trigger();
  const uint64_t t = f.seq;
  f.run(30);
  const FrozenEvent* e = c.take();
  ASSERT_NE(e, nullptr);
  ASSERT_EQ(e->header.sample_count, 530u);
  for (uint32_t i = 0; i < 530; ++i) ASSERT_EQ(e->samples[i].seq, t - 500 + i);
  c.release(e);
}

TEST(Capture, OneEventPerIncidentAndRearmAfterHold) {
  FloatingCapture c;
  c.configure(small_params(), k_angles, k_rate);
  Feeder f{c};
  f.run(200);
  // External input held high for far longer than one window: one event only.
  f.run(1000, flag_external_trigger);
  const FrozenEvent* e = c.take();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->header.cause, TriggerCause::external_input);
  c.release(e);
  EXPECT_EQ(c.take(), nullptr);
  EXPECT_EQ(c.mode(), FloatingCapture::Mode::holdoff) << "re-armed while the condition persisted";
  // Clear for less than the hold: still not armed.
  f.run(40);
  EXPECT_EQ(c.mode(), FloatingCapture::Mode::holdoff);
  f.run(20);
  EXPECT_EQ(c.mode(), FloatingCapture::Mode::armed);
  f.run(20, flag_external_trigger);
  f.run(300);
  e = c.take();
  ASSERT_NE(e, nullptr);
  c.release(e);
  EXPECT_EQ(c.counters().events_frozen, 2u);
}

TEST(Capture, ExternalInputIsDebounced) {
  FloatingCapture c;
  c.configure(small_params(), k_angles, k_rate);  // external debounce 1 ms = 10 samples
  Feeder f{c};
  f.run(200);
  for (int k = 0; k < 20; ++k) {
    f.run(9, flag_external_trigger);  // glitches shorter than the debounce
    f.run(5);
  }
  EXPECT_EQ(c.counters().triggers, 0u);
  f.run(10, flag_external_trigger);
  EXPECT_EQ(c.counters().triggers, 1u);
}

TEST(Capture, OrbitTriggerUsesTheSensorAnglesAndHysteresis) {
  CaptureParams p = small_params();
  p.triggers.orbit.limit_m = 0.2e-3;
  p.triggers.orbit.hysteresis_m = 0.02e-3;
  p.triggers.orbit.debounce_s = 0.0005;  // 5 samples
  TriggerMonitor m;
  m.configure(p.triggers, k_angles, k_rate);
  auto at_radius = [](double r_m, double dir_deg) {
    LoopSample s = synthetic_sample(0);
    // Sensor reading s = x sin(a) + y cos(a), for a point at r in direction dir from vertical.
    const double x = r_m * std::sin(dir_deg * M_PI / 180), y = r_m * std::cos(dir_deg * M_PI / 180);
    const double a = M_PI / 4;
    s.displacement_m = {static_cast<float>(x * std::sin(a) + y * std::cos(a)),
                        static_cast<float>(-x * std::sin(a) + y * std::cos(a)), 0.f, 0.f};
    return s;
  };
  // 0.19 mm straight up reads 0.134 mm on each sensor: below the limit.
  for (int i = 0; i < 20; ++i) EXPECT_EQ(m.update(at_radius(0.19e-3, 0.0), false), 0u);
  EXPECT_NEAR(m.last_orbit_radius_m(), 0.19e-3, 1e-8);
  uint32_t rising = 0;
  for (int i = 0; i < 5; ++i) rising |= m.update(at_radius(0.21e-3, 120.0), false);
  EXPECT_EQ(rising, cause_bit(TriggerCause::orbit_radius));
  // Inside the hysteresis band it stays asserted; below it clears.
  m.update(at_radius(0.19e-3, 120.0), false);
  EXPECT_EQ(m.asserted(), cause_bit(TriggerCause::orbit_radius));
  m.update(at_radius(0.17e-3, 120.0), false);
  EXPECT_EQ(m.asserted(), 0u);
}

TEST(Capture, OrbitIsNotSupervisedWhileResting) {
  TriggerMonitor m;
  m.configure(TriggerParams{}, k_angles, k_rate);
  LoopSample s = synthetic_sample(0);
  s.displacement_m = {-0.3e-3f, -0.3e-3f, -0.3e-3f, -0.3e-3f};  // on the touchdown bearings
  s.flags = 0;
  s.phase = static_cast<uint8_t>(Phase::idle);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(m.update(s, false), 0u);
}

TEST(Capture, CurrentSaturationAndCutoffTriggers) {
  TriggerParams tp;
  TriggerMonitor m;
  m.configure(tp, k_angles, k_rate);
  LoopSample s = synthetic_sample(0);
  s.coil_current_a[2] = 2.3f;
  uint32_t r = 0;
  for (int i = 0; i < 10; ++i) r |= m.update(s, false);
  EXPECT_EQ(r, cause_bit(TriggerCause::current_limit));

  m.configure(tp, k_angles, k_rate);
  r = 0;
  for (int i = 0; i < 10; ++i) r |= m.update(synthetic_sample(0, flag_saturated), false);
  EXPECT_EQ(r, cause_bit(TriggerCause::saturation));

  m.configure(tp, k_angles, k_rate);
  s = synthetic_sample(0);
  s.coil_current_a[1] = 0.0f;
  s.current_demand_a[1] = 0.8f;
  r = 0;
  for (int i = 0; i < 19; ++i) r |= m.update(s, false);
  EXPECT_EQ(r, 0u) << "cut-off asserted before its 2 ms debounce";
  r |= m.update(s, false);
  EXPECT_EQ(r, cause_bit(TriggerCause::channel_cutoff));
  EXPECT_EQ(m.cutoff_channels(), 0x2);
}

TEST(Capture, SwitchOffAndLandingEdges) {
  TriggerMonitor m;
  m.configure(TriggerParams{}, k_angles, k_rate);
  LoopSample s = synthetic_sample(0);
  EXPECT_EQ(m.update(s, false), 0u);
  LoopSample land = s;
  land.phase = static_cast<uint8_t>(Phase::spinning_down);
  EXPECT_EQ(m.update(land, false), cause_bit(TriggerCause::landing_command));
  EXPECT_EQ(m.update(land, false), 0u) << "an edge asserts once";
  LoopSample off = land;
  off.flags = 0;
  off.state = static_cast<uint8_t>(State::fault);
  off.phase = static_cast<uint8_t>(Phase::idle);
  EXPECT_EQ(m.update(off, false), cause_bit(TriggerCause::amb_switch_off));
  EXPECT_EQ(m.update(off, false), 0u);
}

TEST(Capture, DisabledTriggersDoNotFire) {
  CaptureParams p = small_params();
  p.triggers.external.enabled = false;
  p.triggers.manual.enabled = false;
  FloatingCapture c;
  c.configure(p, k_angles, k_rate);
  EXPECT_FALSE(c.request_manual_trigger());
  Feeder f{c};
  f.run(500, flag_external_trigger);
  EXPECT_EQ(c.counters().triggers, 0u);
}

TEST(Capture, EventIsLostNotWaitedForWhenNoBufferIsFree) {
  CaptureParams p = small_params();
  p.event_buffers = 1;
  FloatingCapture c;
  c.configure(p, k_angles, k_rate);
  Feeder f{c};
  f.run(200);
  c.request_manual_trigger();
  f.run(300);  // frozen, not taken
  c.request_manual_trigger();
  f.run(300);
  const CaptureCounters k = c.counters();
  EXPECT_EQ(k.events_frozen, 1u);
  EXPECT_EQ(k.events_lost, 1u);
  const FrozenEvent* e = c.take();
  ASSERT_NE(e, nullptr);
  c.release(e);
  f.run(100);
  c.request_manual_trigger();
  f.run(300);
  e = c.take();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->header.events_lost_before, 1u);
  c.release(e);
}

TEST(Capture, OnSampleNeverAllocates) {
  CaptureParams p;  // board defaults: 0.5 s + 2 s at 10 kHz
  FloatingCapture c;
  c.configure(p, k_angles, k_rate);
  uint64_t seq = 0;
  std::vector<LoopSample> samples;
  samples.reserve(4);
  const long before = amb::test::allocations();
  for (int ev = 0; ev < 3; ++ev) {
    for (int i = 0; i < 10000; ++i) c.on_sample(synthetic_sample(seq++));
    c.request_manual_trigger();
    for (int i = 0; i < 30000; ++i) c.on_sample(synthetic_sample(seq++, i < 5000 ? flag_saturated : 0u));
    if (const FrozenEvent* e = c.take()) c.release(e);
  }
  EXPECT_EQ(amb::test::allocations() - before, 0) << "the real-time path allocated";
  EXPECT_EQ(c.counters().events_frozen, 3u);
}

}  // namespace
