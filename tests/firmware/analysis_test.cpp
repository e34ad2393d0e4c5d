// The board's analysis task: the loop -> analysis hand-off (SPSC ring: no allocation, a full
// ring drops and counts), the speed source, the tracker/tach disagreement counter, and a
// tracker that loses the line (silent channel, speed out of range): lost in the register, in
// the sample and in the stored event, never the last good value.
#include "tests/firmware/alloc_counter.hpp"  // the counter is defined in supervisor_test.cpp

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "firmware/analysis/analysis_task.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/event_record.hpp"
#include "firmware/supervisory/register_map.hpp"

using namespace amb::fw;

namespace {

/// The bath board (10 kHz, tracker on sensor A1, orders [1]) with the tracker as the speed
/// source; a supervisor and an analysis task on it; the loop driven with synthetic samples.
class AnalysisTest : public ::testing::Test {
 protected:
  void SetUp() override {
    board = amb::board::load_board("bath-amb-rig");
    board.tracker.speed_source = SpeedSource::tracker;
    sup.configure(board);
    ASSERT_EQ(task->configure(board, &sup), "");
    ASSERT_TRUE(task->enabled());
    poll_every = static_cast<int>(std::lround(board.tracker.poll_period_s * board.rate_hz));
    samples.reserve(200000);  // the test's own record must not allocate inside the measured runs
  }
  /// `seconds` of loop periods with a line at `f_hz` (amplitude 5 um, 0.5 um noise) on the
  /// tracker channel; `ok` false: the front end delivers nothing (silent channel).
  void run(double seconds, double f_hz, bool ok = true, double tach_hz = -1.0) { ramp(seconds, f_hz, f_hz, ok, tach_hz); }
  /// Like run(), the line's frequency going linearly from f0_hz to f1_hz (a spin-up).
  void ramp(double seconds, double f0_hz, double f1_hz, bool ok = true, double tach_hz = -1.0) {
    const int n = static_cast<int>(std::lround(seconds * board.rate_hz));
    std::normal_distribution<double> noise(0.0, 0.5e-6);
    for (int i = 0; i < n; ++i) {
      in.t_ns += 100000;
      const double f_hz = f0_hz + (f1_hz - f0_hz) * static_cast<double>(i) / static_cast<double>(n);
      phase += 2.0 * M_PI * f_hz / board.rate_hz;
      in.displacement_m[0] = 5e-6 * std::sin(phase) + noise(rng);
      in.displacement_m[1] = noise(rng);
      in.tach_speed_hz = tach_hz;
      sup.step(in, ok, din, out, dout);
      task->on_sample(sup.last_sample());
      samples.push_back(sup.last_sample());
      if (++since_poll >= poll_every) {
        since_poll = 0;
        task->poll();
      }
    }
  }
  std::vector<uint16_t> speed_registers() {
    RegisterSources src;
    src.supervisor = &sup;
    src.analysis = [this] { return task->status(); };
    src.speed_source = static_cast<uint8_t>(board.tracker.speed_source);
    RegisterMap map(src);
    std::vector<uint16_t> r(regs::speed_end - regs::speed_estimate_mhz);
    EXPECT_EQ(map.read_registers(regs::speed_estimate_mhz, r), amb::hal::RegisterHandler::ok);
    return r;
  }
  static int32_t i32(const std::vector<uint16_t>& r, size_t at) {
    return static_cast<int32_t>(static_cast<uint32_t>(r[at]) << 16 | r[at + 1]);
  }
  /// The last `n` samples as a stored event (trigger on the last one), through the codec.
  EventRecord event_of_last(size_t n) {
    EventRecord r;
    r.samples.assign(samples.end() - static_cast<long>(n), samples.end());
    r.meta.rate_hz = board.rate_hz;
    r.meta.trigger_index = static_cast<uint32_t>(n - 1);
    r.meta.speed_at_trigger_hz = r.samples.back().speed_hz;
    BearingTask unconfigured;
    r.analysis = event_analysis(r, board, unconfigured);
    r.has_analysis = true;
    EventRecord back;
    std::string err;
    EXPECT_TRUE(decode_event(encode_event(r), back, err)) << err;
    return back;
  }

  amb::board::BoardConfig board;
  Supervisor sup;
  std::unique_ptr<AnalysisTask> task = std::make_unique<AnalysisTask>();
  amb::hal::AnalogInputs in{};
  amb::hal::DiscreteInputs din{};
  amb::hal::AnalogOutputs out{};
  amb::hal::DiscreteOutputs dout{};
  std::mt19937 rng{7};
  double phase = 0.0;
  int poll_every = 200, since_poll = 0;
  std::vector<LoopSample> samples;
};

TEST_F(AnalysisTest, RingHandOffAllocatesNothingAndAFullRingDropsAndCounts) {
  const size_t extra = 1000;
  const size_t n = k_tracker_ring_capacity + extra;
  LoopSample s;
  const long a0 = amb::test::allocations();
  for (size_t i = 0; i < n; ++i) {
    s.seq = i;
    s.t_ns = static_cast<int64_t>(i) * 100000;
    s.displacement_m[0] = static_cast<float>(1e-6 * std::sin(0.03 * static_cast<double>(i)));
    task->on_sample(s);
  }
  EXPECT_EQ(amb::test::allocations() - a0, 0) << "on_sample (loop side) allocated";
  EXPECT_EQ(task->ring_drops(), extra);
  // A sample whose read failed is not handed over (the tracker sees a gap, not a held value).
  s.seq = n;
  s.flags = flag_read_failed;
  task->on_sample(s);
  EXPECT_EQ(task->ring_drops(), extra);
  const long a1 = amb::test::allocations();
  const size_t consumed = task->poll();
  EXPECT_EQ(amb::test::allocations() - a1, 0) << "poll (analysis side) allocated";
  EXPECT_EQ(consumed, k_tracker_ring_capacity);
  EXPECT_EQ(task->status().ring_drops, extra);
  // The loop's step with the tracked speed source and the hand-off stays allocation-free.
  const long a2 = amb::test::allocations();
  run(0.2, 45.0);
  EXPECT_EQ(amb::test::allocations() - a2, 0);
}

TEST_F(AnalysisTest, TrackedSpeedIsTheEstimateAndASilentChannelMakesItLost) {
  ramp(1.5, 0.0, 45.0);  // spin-up at 30 Hz/s as on the rig, then at speed
  run(3.0, 45.0);
  Status st = sup.status();
  ASSERT_FALSE(st.speed_lost) << "tracker did not lock on a 45 Hz line";
  // The estimate is the tracker's, everywhere it is published, and a clean tone reads true
  // (it used to read ~35.8 Hz: the run-up's frame warp stayed on after the ramp; see
  // tests/tracking/speed_tracker_test.cpp SteadyLineAfterARunUpReadsTrue).
  EXPECT_NEAR(st.speed_estimate_hz, 45.0, 0.05);
  EXPECT_GT(st.speed_confidence, 0.3);
  EXPECT_EQ(st.speed_estimate_hz, st.tracked.speed_hz);
  EXPECT_FALSE(speed_lost(samples.back()));
  EXPECT_FLOAT_EQ(samples.back().speed_hz, static_cast<float>(st.speed_estimate_hz));
  auto r = speed_registers();
  EXPECT_NEAR(i32(r, 0) * 1e-3, st.speed_estimate_hz, 1e-3);
  EXPECT_EQ(r[5] & 1u, 0u);
  EXPECT_EQ((r[5] >> 3) & 3u, 1u) << "speed source bits";
  EXPECT_NEAR(i32(r, 6) * 1e-3, st.speed_estimate_hz, 1e-3);
  {
    const EventRecord e = event_of_last(100);
    EXPECT_FALSE(e.analysis.speed_lost_at_trigger);
    EXPECT_GT(e.analysis.speed_confidence_at_trigger, 0.3);
    EXPECT_EQ(e.analysis.speed_source, static_cast<uint8_t>(SpeedSource::tracker));
  }

  // The channel goes silent: no sample reaches the tracker, so it never updates again. The
  // last lock must turn into "lost" within stale_after_s, not stay on display.
  run(board.tracker.stale_after_s + 0.05, 45.0, /*ok=*/false);
  st = sup.status();
  EXPECT_TRUE(st.speed_lost);
  EXPECT_TRUE(st.tracked.stale);
  EXPECT_TRUE(std::isnan(st.speed_estimate_hz));
  EXPECT_TRUE(speed_lost(samples.back()));
  EXPECT_TRUE(std::isnan(samples.back().speed_hz));
  r = speed_registers();
  EXPECT_EQ(i32(r, 0), regs::k_speed_invalid);
  EXPECT_EQ(i32(r, 6), regs::k_speed_invalid);
  EXPECT_EQ(r[5] & 3u, 3u) << "lost and stale flags";
  EXPECT_GT(sup.status().counters.speed_lost_periods, 0u);
  const EventRecord e = event_of_last(100);
  EXPECT_TRUE(e.analysis.speed_lost_at_trigger);
  EXPECT_EQ(e.analysis.speed_confidence_at_trigger, 0.0);
  EXPECT_TRUE(std::isnan(e.meta.speed_at_trigger_hz));
}

// The line jumps above the tracker's range: once the tracker's window no longer holds it, the
// tracker coasts on noise in its search band (confidence 0.15-0.3, never "lost" by its own
// rule); the board publishes such updates as lost (min_confidence), in the register, in every
// loop sample and in the stored event.
TEST_F(AnalysisTest, ASpeedBeyondTheTrackerRangeIsLostNotTheLastLock) {
  ramp(1.5, 0.0, 45.0);
  run(3.0, 45.0);
  ASSERT_FALSE(sup.status().speed_lost);
  EXPECT_NEAR(sup.status().speed_estimate_hz, 45.0, 0.05) << "a clean tone reads true";
  // The line jumps above max_speed_hz (200 Hz): the samples keep coming, the tracker keeps
  // updating, and it must say lost once its 1 s window has let go of the old line.
  const size_t before = samples.size();
  run(1.5, 260.0);
  const Status st = sup.status();
  EXPECT_FALSE(st.tracked.stale) << "the tracker still updates";
  EXPECT_TRUE(st.speed_lost);
  EXPECT_TRUE(std::isnan(st.speed_estimate_hz));
  EXPECT_EQ(task->status().lost, 1);
  EXPECT_LT(task->status().confidence, board.tracker.min_confidence);
  EXPECT_EQ(i32(speed_registers(), 0), regs::k_speed_invalid);
  EXPECT_EQ(speed_registers()[5] & 1u, 1u) << "lost flag";
  EXPECT_TRUE(event_of_last(50).analysis.speed_lost_at_trigger);
  // From 1.2 s after the jump (window + two hops) no loop sample carries a speed.
  size_t with_speed = 0;
  const size_t from = before + static_cast<size_t>(1.2 * board.rate_hz);
  for (size_t i = from; i < samples.size(); ++i)
    if (!speed_lost(samples[i]) || std::isfinite(samples[i].speed_hz)) ++with_speed;
  EXPECT_EQ(with_speed, 0u) << "of " << samples.size() - from << " samples";
}

TEST_F(AnalysisTest, TrackerTachDisagreementIsCountedOncePerUpdate) {
  const double frac = board.tracker.tach_disagreement_fraction;
  in.tach_speed_hz = 45.0;
  sup.publish_tracked_speed(45.0 * (1.0 + 0.5 * frac), 0.9, false);  // within the threshold
  for (int i = 0; i < 10; ++i) sup.step(in, true, din, out, dout);
  EXPECT_EQ(sup.status().counters.speed_disagreements, 0u);
  sup.publish_tracked_speed(45.0 * (1.0 + 2.0 * frac), 0.9, false);  // beyond it
  for (int i = 0; i < 10; ++i) sup.step(in, true, din, out, dout);
  EXPECT_EQ(sup.status().counters.speed_disagreements, 1u);
  sup.publish_tracked_speed(45.0, 0.1, true);  // lost: not compared
  for (int i = 0; i < 10; ++i) sup.step(in, true, din, out, dout);
  EXPECT_EQ(sup.status().counters.speed_disagreements, 1u);
}

}  // namespace

// The loop's wake-up latency histogram (amb-bench, registers 0x0400..): allocation-free,
// fixed size, and wide enough that p99 is a number on a loaded or emulated machine (it used to
// saturate at its 128 us top).
TEST(LoopStats, LatencyHistogramResolvesMillisecondsAndSeconds) {
  EXPECT_EQ(LoopStats::bin_of(0), 0);
  EXPECT_EQ(LoopStats::bin_of(1999), 0);
  EXPECT_EQ(LoopStats::bin_of(2000), 1);
  EXPECT_EQ(LoopStats::bin_of(127999), 63);
  EXPECT_EQ(LoopStats::bin_of(128000), 64);
  EXPECT_EQ(LoopStats::bin_of(int64_t{1} << 62), LoopStats::k_bins - 1);
  // Bins are contiguous and increasing, each no wider than 1/16 of its lower edge above 128 us.
  int64_t lower = 0;
  for (int b = 0; b + 1 < LoopStats::k_bins; ++b) {
    const int64_t upper = LoopStats::bin_upper_ns(b);
    ASSERT_GT(upper, lower);
    EXPECT_EQ(LoopStats::bin_of(lower), b) << "bin " << b;
    EXPECT_EQ(LoopStats::bin_of(upper - 1), b) << "bin " << b;
    if (lower >= LoopStats::k_linear_top_ns) {
      EXPECT_LE(upper - lower, lower / 16 + 1);
    }
    lower = upper;
  }
  EXPECT_GT(lower, int64_t{2'000'000'000}) << "top of the last finite bin";
  // p99 of 1000 periods: 985 at 20 us, 15 at 3.3 ms -> the bin holding 3.3 ms (within 6.25 %).
  LoopStats s;
  for (int i = 0; i < 1000; ++i) {
    const int64_t lat = i < 985 ? 20'000 : 3'300'000;
    ++s.latency_hist[static_cast<size_t>(LoopStats::bin_of(lat))];
    ++s.periods;
    s.max_latency_ns = std::max(s.max_latency_ns, lat);
  }
  EXPECT_EQ(s.latency_quantile_ns(0.5), 22'000);
  EXPECT_EQ(s.latency_quantile_ns(0.99), 3'300'000) << "bin edge capped at the largest latency seen";
  s.max_latency_ns = 4'000'000;
  EXPECT_GE(s.latency_quantile_ns(0.99), 3'300'000);
  EXPECT_LE(s.latency_quantile_ns(0.99), 3'300'000 + 3'300'000 / 16);
}
