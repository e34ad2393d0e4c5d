// Loop undisturbed by the analysis thread: the 10 kHz loop (bath board, absolute-deadline
// sleeps on CLOCK_MONOTONIC, SCHED_FIFO when permitted) runs for a few seconds of wall time
// with the analysis thread off (/0) and on (/1); a synthetic front end puts a 45 Hz line on
// the tracker channel so the tracker does its full work. Reported per case: wake-up latency
// p99 / mean / max, overruns, ring drops, the tracked speed, and the CPU share (CPU time / wall
// time, 1 = one CPU) of the loop thread and of the analysis thread, read from their thread CPU
// clocks before and after the run (never inside the loop step). One run gives both side by side:
//   build/tests/bench/amb-bench --benchmark_filter=LoopWakeLatency
// AMB_BENCH_LOOP_S sets the seconds per case (default 3).
#include <benchmark/benchmark.h>
#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <thread>

#include "firmware/analysis/analysis_thread.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/sample_fanout.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "tests/bench/mono_clock.hpp"

namespace {

using namespace amb;

/// CPU time of a thread so far, ns (its CLOCK_THREAD_CPUTIME clock); -1 if unreadable.
int64_t thread_cpu_ns(pthread_t t) {
  clockid_t cid;
  timespec ts{};
  if (::pthread_getcpuclockid(t, &cid) != 0 || ::clock_gettime(cid, &ts) != 0) return -1;
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

using bench::MonoClock;
using bench::mono_ns;

/// A rotor line at 45 Hz (5 um) on sensor A1, from the sample's own time stamp.
class LineFrontEnd final : public hal::AnalogFrontEnd {
 public:
  bool read(hal::AnalogInputs& in) override {
    in.t_ns = mono_ns();
    k_ += 1;
    in.displacement_m[0] = 5e-6 * std::sin(2.0 * M_PI * 45.0 * static_cast<double>(k_) * 1e-4);
    in.tach_speed_hz = -1.0;
    return true;
  }
  void write(const hal::AnalogOutputs&) override {}

 private:
  uint64_t k_ = 0;
};

class NullDio final : public hal::DiscreteIo {
 public:
  hal::DiscreteInputs read() override { return {}; }
  void write(const hal::DiscreteOutputs&) override {}
};

void BM_LoopWakeLatency(benchmark::State& state) {
  const bool with_analysis = state.range(0) != 0;
  const char* env = std::getenv("AMB_BENCH_LOOP_S");
  const double seconds = env ? std::atof(env) : 3.0;
  board::BoardConfig b = board::load_board("bath-amb-rig");
  b.tracker.speed_source = fw::SpeedSource::tracker;
  fw::Supervisor sup;
  sup.configure(b);
  auto task = std::make_unique<fw::AnalysisTask>();
  if (!task->configure(b, &sup).empty()) {
    state.SkipWithError("analysis task refused the bath board");
    return;
  }
  fw::SampleFanout sinks;
  if (with_analysis) sinks.add(task.get());
  MonoClock clock;
  LineFrontEnd afe;
  NullDio dio;
  fw::LoopRunner loop(clock, afe, dio, sup, &sinks);
  fw::AnalysisThread thread;
  if (with_analysis) thread.start(*task, b.tracker.poll_period_s);
  const auto periods = static_cast<uint64_t>(seconds * b.rate_hz);
  bool fifo = false;
  int64_t loop_cpu_ns = 0, loop_wall_ns = 0, analysis_cpu_ns = 0;
  for (auto _ : state) {
    const int64_t a0 = with_analysis ? thread_cpu_ns(thread.native_handle()) : 0;
    // The loop in its own thread, SCHED_FIFO 80 when permitted (as amb-firmware does).
    std::thread t([&] {
      sched_param sp{};
      sp.sched_priority = 80;
      fifo = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &sp) == 0;
      const int64_t c0 = thread_cpu_ns(::pthread_self()), w0 = mono_ns();
      loop.run_periods(periods);
      loop_cpu_ns = thread_cpu_ns(::pthread_self()) - c0;
      loop_wall_ns = mono_ns() - w0;
    });
    t.join();
    if (with_analysis) analysis_cpu_ns = thread_cpu_ns(thread.native_handle()) - a0;
    state.SetIterationTime(seconds);
  }
  thread.stop();
  const fw::LoopStats& ls = loop.stats();
  const fw::AnalysisStatus a = task->status();
  state.counters["p99_us"] = static_cast<double>(ls.latency_quantile_ns(0.99)) * 1e-3;
  state.counters["mean_us"] = ls.mean_latency_ns() * 1e-3;
  state.counters["max_us"] = static_cast<double>(ls.max_latency_ns) * 1e-3;
  state.counters["overruns"] = static_cast<double>(ls.overruns);
  state.counters["periods"] = static_cast<double>(ls.periods);
  state.counters["ring_drops"] = static_cast<double>(task->ring_drops());
  state.counters["tracker_updates"] = static_cast<double>(a.tracker_updates);
  state.counters["tracked_hz"] = with_analysis && !a.lost ? a.tracked_speed_hz : 0.0;
  state.counters["sched_fifo"] = fifo ? 1.0 : 0.0;
  state.counters["loop_cpu_pct"] = loop_wall_ns > 0 ? 100.0 * static_cast<double>(loop_cpu_ns) / static_cast<double>(loop_wall_ns) : -1.0;
  state.counters["analysis_cpu_pct"] =
      with_analysis && loop_wall_ns > 0 ? 100.0 * static_cast<double>(analysis_cpu_ns) / static_cast<double>(loop_wall_ns) : 0.0;
  state.SetLabel(with_analysis ? "analysis thread on" : "analysis thread off");
}
BENCHMARK(BM_LoopWakeLatency)->ArgName("analysis")->Arg(0)->Arg(1)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
