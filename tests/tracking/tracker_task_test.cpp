// Firmware tracker task: a producer thread offers samples into the SPSC ring, the tracker
// thread polls, a reader thread reads the published estimate lock-free, never torn.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <thread>

#include "firmware/tracking/speed_tracker_task.hpp"
#include "tests/tracking/test_signals.hpp"

TEST(TrackerTask, ThreadsProduceTrackAndPublish) {
  auto task = std::make_unique<amb::fw::SpeedTrackerTask>();
  amb::model::signal::SpeedTrackerOptions o;
  ASSERT_EQ(task->configure(o), "");
  auto speed = [](double) { return 55.0; };
  const auto x = amb::test::synthetic_machine(speed, {{1.0, 1.0, 0.0}, {2.0, 0.5, 0.0}}, 10000.0, 5.0, 0.2, 9);
  std::atomic<bool> done{false};
  std::atomic<bool> torn{false};
  std::thread producer([&] {
    for (size_t i = 0; i < x.size(); ++i) {
      while (!task->offer({i, static_cast<int64_t>(i) * 100000, x[i]})) std::this_thread::yield();
    }
    done = true;
  });
  std::thread reader([&] {
    uint64_t last = 0;
    while (!done) {
      const auto s = task->latest();
      // Consistency of a snapshot: a valid speed is never flagged lost, seq never goes back.
      if (s.update_seq < last || (s.lost == 0 && !std::isfinite(s.speed_hz))) torn = true;
      last = s.update_seq;
    }
  });
  while (!done) {
    task->poll(4096);
    std::this_thread::yield();
  }
  producer.join();
  reader.join();
  while (task->poll() > 0) {
  }
  const auto s = task->latest();
  EXPECT_FALSE(torn.load());
  EXPECT_EQ(task->counters().samples, x.size());
  EXPECT_EQ(s.lost, 0);
  // One update's scatter on this signal (1x at 0.2 rms noise, 0.5 s window) is about
  // +-0.15 Hz; the tracker's accuracy is the subject of speed_tracker_test.cpp.
  EXPECT_NEAR(s.speed_hz, 55.0, 0.25);
  // Window centre of the last update, in HAL time: about 4.75 s after the first sample.
  EXPECT_NEAR(static_cast<double>(s.t_ns) * 1e-9, 4.75, 0.06);
}

TEST(TrackerTask, LongGapResetsTheTracker) {
  auto task = std::make_unique<amb::fw::SpeedTrackerTask>();
  ASSERT_EQ(task->configure(amb::model::signal::SpeedTrackerOptions{}, 8), "");
  for (uint64_t i = 0; i < 100; ++i) task->offer({i, 0, 0.0});
  task->offer({1000, 0, 0.0});
  task->poll();
  EXPECT_EQ(task->counters().resets, 1u);
  EXPECT_EQ(task->counters().gaps, 1u);
}
