// Real-time thread set-up and the loop on the Linux clock: affinity and SCHED_FIFO are
// really applied (or the reason is reported), and a 1 s loop at 10 kHz on absolute
// deadlines runs against the sim plant with its latency histogram filled. Also the ordinary
// threads' scheduling (hal::ThreadScheduling).
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "firmware/analysis/analysis_thread.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/board/board.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "hal/linux/linux_clock.hpp"
#include "hal/linux/rt_thread.hpp"
#include "hal/linux/thread_scheduling.hpp"

using namespace amb;

TEST(RtThread, AffinityAndSchedulerAreAppliedOrExplained) {
  std::thread t([] {
    hal::linux_hw::RtOptions o;
    o.cpu = 0;
    o.fifo_priority = 10;
    o.lock_memory = false;  // keep the test process's memory policy unchanged
    const auto r = hal::linux_hw::configure_realtime_thread(o);
    EXPECT_TRUE(r.pinned) << r.warnings;
    EXPECT_EQ(sched_getcpu(), 0);
    int policy = 0;
    sched_param sp{};
    pthread_getschedparam(pthread_self(), &policy, &sp);
    if (r.fifo) {
      EXPECT_EQ(policy, SCHED_FIFO);
      EXPECT_EQ(sp.sched_priority, 10);
    } else {
      EXPECT_FALSE(r.warnings.empty());  // not privileged: said why
      std::printf("[ NOTE ] SCHED_FIFO not applied here: %s\n", r.warnings.c_str());
    }
  });
  t.join();
}

TEST(RtThread, LoopOnAbsoluteDeadlinesFillsTheLatencyHistogram) {
  const board::BoardConfig b = board::load_board("bath-amb-rig");
  sil::SilRig rig(b);
  hal::linux_hw::LinuxClock clock;
  fw::LoopRunner loop(clock, rig.sim().analog(), rig.sim().discrete(), rig.supervisor());
  loop.run_periods(static_cast<uint64_t>(0.2 * b.rate_hz));
  const fw::LoopStats& s = loop.stats();
  uint64_t counted = 0;
  for (uint64_t c : s.latency_hist) counted += c;
  EXPECT_EQ(s.periods, static_cast<uint64_t>(0.2 * b.rate_hz));
  EXPECT_EQ(counted, s.periods);
  EXPECT_GT(s.max_latency_ns, 0);  // a real clock always wakes a little late
  std::printf("[ RESULT ] 0.2 s at %.0f Hz on CLOCK_MONOTONIC: mean latency %.1f us, p99 %.1f us, max %.1f us, overruns %llu\n",
              b.rate_hz, s.mean_latency_ns() * 1e-3, static_cast<double>(s.latency_quantile_ns(0.99)) * 1e-3,
              static_cast<double>(s.max_latency_ns) * 1e-3, static_cast<unsigned long long>(s.overruns));
}

TEST(RtThread, PinsToTheHighestAllowedCpu) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  ASSERT_EQ(sched_getaffinity(0, sizeof allowed, &allowed), 0);
  int highest = -1;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &allowed)) highest = c;
  std::thread t([&] {
    hal::linux_hw::RtOptions o;
    o.fifo_priority = 0;
    o.lock_memory = false;
    o.pin_highest_allowed = true;
    const auto r = hal::linux_hw::configure_realtime_thread(o);
    if (CPU_COUNT(&allowed) < 2) {
      EXPECT_FALSE(r.pinned);  // a one-CPU set is left alone
      return;
    }
    EXPECT_TRUE(r.pinned) << r.warnings;
    EXPECT_EQ(r.cpu, highest);
    EXPECT_EQ(sched_getcpu(), highest);
  });
  t.join();
}

// The ordinary threads' scheduling through the HAL (hal::ThreadScheduling): the linux
// backend's nice value is the calling thread's only, and the analysis thread applies the
// scheduling it is given to itself, once, in its own thread.
TEST(ThreadScheduling, LinuxBackgroundNiceIsTheCallingThreadsOnly) {
  const int before = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
  if (before > 10) GTEST_SKIP() << "the test runs at nice " << before << " already (lowering it needs privilege)";
  hal::linux_hw::LinuxThreadScheduling s(10);
  bool applied = false;
  int nice_in_thread = -100;
  std::thread t([&] {
    applied = s.make_current_thread_background();
    nice_in_thread = ::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()));
  });
  t.join();
  EXPECT_TRUE(applied);  // raising one's own nice value needs no privilege
  EXPECT_EQ(nice_in_thread, 10);
  EXPECT_EQ(::getpriority(PRIO_PROCESS, static_cast<id_t>(::gettid())), before);
}

namespace {
struct RecordingScheduling final : hal::ThreadScheduling {
  std::atomic<int> calls{0};
  std::thread::id caller;
  bool make_current_thread_background() override {
    caller = std::this_thread::get_id();
    calls.fetch_add(1);
    return true;
  }
};
}  // namespace

TEST(ThreadScheduling, AnalysisThreadAppliesItToItselfOnce) {
  const board::BoardConfig board = board::load_board("bath-amb-rig");
  fw::AnalysisTask task;
  ASSERT_EQ(task.configure(board, nullptr), "");
  RecordingScheduling s;
  fw::AnalysisThread thread(&s);
  thread.start(task, 0.002);
  for (int i = 0; i < 500 && s.calls.load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a few polls more
  thread.stop();
  EXPECT_EQ(s.calls.load(), 1);
  EXPECT_NE(s.caller, std::this_thread::get_id());
  // Without a scheduling (the sim backend) the thread runs as it is.
  fw::AnalysisThread plain;
  plain.start(task, 0.002);
  plain.stop();
}
