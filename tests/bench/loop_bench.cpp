// Control loop benchmarks: the cost of one control step (all axes), allocations per step,
// one full SIL period (firmware + sim plant), and the achieved loop period over 10 s of SIL
// paced to wall time with absolute-deadline sleeps.
#include <benchmark/benchmark.h>
#include <time.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/sil/sil_rig.hpp"

// Allocation counter for this benchmark binary (reported as a counter, must stay 0).
namespace {
std::atomic<long> g_allocs{0};
}
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  g_allocs.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

using namespace amb;

// A configured supervisor and its I/O, with the levitate command posted.
struct StepRig {
  fw::Supervisor sup;
  hal::AnalogInputs in{};
  hal::DiscreteInputs din{};
  hal::AnalogOutputs out{};
  hal::DiscreteOutputs dout{};
  explicit StepRig(const board::BoardConfig& b) {
    sup.configure(b);
    sup.post(fw::Command::levitate);
  }
  void step() {
    in.t_ns += 100000;
    sup.step(in, true, din, out, dout);
  }
};

// The timed part: one 10 kHz step per iteration with a moving A1 reading; allocations per step
// counted by the interposed operator new (counter allocs_per_step).
void timed_steps(benchmark::State& state, StepRig& r) {
  long k = 0;
  const long a0 = g_allocs.load();
  for (auto _ : state) {
    r.in.displacement_m[0] = 1e-6 * std::sin(0.01 * static_cast<double>(++k));
    r.step();
    benchmark::DoNotOptimize(r.out);
  }
  state.counters["allocs_per_step"] = static_cast<double>(g_allocs.load() - a0) / static_cast<double>(state.iterations());
}

void BM_ControlStep(benchmark::State& state) {
  StepRig r(board::load_board("bath-amb-rig"));
  r.sup.step(r.in, true, r.din, r.out, r.dout);
  timed_steps(state, r);
}
BENCHMARK(BM_ControlStep);

// The control step levitated (phase levitated, rotor centred), without and with the
// loop-sensitivity sweep generator running (issue 35): the multisine table lookup at the
// controller output of axis 0 and the four stores of its record, every step. One axis and 200
// recorded 1 s periods (32 MB record buffer, allocated at configure) so that the sweep is
// still recording when the 1.5 M timed steps end (counter sweep_recording = 1).
void control_step_levitated(benchmark::State& state, bool sweep) {
  board::BoardConfig b = board::load_board("bath-amb-rig");
  b.sweep.axes = {true, false, false, false};
  b.sweep.recorded_periods = 200;
  StepRig r(b);
  for (int i = 0; i < static_cast<int>((b.lifecycle.liftoff_ramp_s + b.lifecycle.settle_s) * b.rate_hz) + 20; ++i) r.step();
  if (sweep) r.sup.request_sweep_start();
  timed_steps(state, r);
  const fw::SweepState ss = r.sup.status().sweep.state;
  state.counters["sweep_recording"] = (ss == fw::SweepState::recording || ss == fw::SweepState::settling) ? 1.0 : 0.0;
  state.counters["levitated"] = r.sup.status().phase == fw::Phase::levitated ? 1.0 : 0.0;
}
void BM_ControlStepLevitated(benchmark::State& state) { control_step_levitated(state, false); }
void BM_ControlStepSweep(benchmark::State& state) { control_step_levitated(state, true); }
BENCHMARK(BM_ControlStepLevitated)->Iterations(1500000);
BENCHMARK(BM_ControlStepSweep)->Iterations(1500000);

void BM_SilPeriod(benchmark::State& state, const char* board_name) {
  const board::BoardConfig b = board::load_board(board_name);
  sil::SilRig rig(b);
  rig.run_for(0.01);
  rig.supervisor().post(fw::Command::levitate);
  rig.run_for(0.6);
  const long a0 = g_allocs.load();
  for (auto _ : state) rig.loop().run_periods(1);
  state.counters["allocs_per_period"] = static_cast<double>(g_allocs.load() - a0) / static_cast<double>(state.iterations());
  state.counters["realtime_factor"] = benchmark::Counter(
      static_cast<double>(state.iterations()) / b.rate_hz, benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_SilPeriod, bath, "bath-amb-rig");
BENCHMARK_CAPTURE(BM_SilPeriod, unicamp, "unicamp-amb-rig");

/// A clock that steps the sim plant in lockstep, then sleeps to the same deadline on
/// CLOCK_MONOTONIC (TIMER_ABSTIME) and reports wall time, so the runner's latency histogram
/// measures the real wake-up lateness of a paced SIL loop.
class PacedClock final : public hal::Clock {
 public:
  explicit PacedClock(hal::Clock& sim) : sim_(sim) {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    origin_ns_ = ts.tv_sec * 1000000000LL + ts.tv_nsec - sim.now_ns();
  }
  int64_t now_ns() override {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1000000000LL + ts.tv_nsec - origin_ns_;
  }
  int64_t wait_until_ns(int64_t deadline_ns) override {
    sim_.wait_until_ns(deadline_ns);
    const int64_t abs_ns = origin_ns_ + deadline_ns;
    timespec ts{static_cast<time_t>(abs_ns / 1000000000LL), static_cast<long>(abs_ns % 1000000000LL)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
    }
    return now_ns();
  }

 private:
  hal::Clock& sim_;
  int64_t origin_ns_ = 0;
};

void BM_PacedSilLoopPeriod(benchmark::State& state) {
  const board::BoardConfig b = board::load_board("bath-amb-rig");
  for (auto _ : state) {
    sil::SilRig rig(b);
    rig.run_for(0.01);
    rig.supervisor().post(fw::Command::levitate);
    PacedClock paced(rig.sim().clock());
    fw::LoopRunner loop(paced, rig.sim().analog(), rig.sim().discrete(), rig.supervisor());
    loop.run_periods(static_cast<uint64_t>(10.0 * b.rate_hz));  // 10 s
    const fw::LoopStats& s = loop.stats();
    state.counters["periods"] = static_cast<double>(s.periods);
    state.counters["overruns"] = static_cast<double>(s.overruns);
    state.counters["latency_mean_us"] = s.mean_latency_ns() * 1e-3;
    state.counters["latency_p50_us"] = static_cast<double>(s.latency_quantile_ns(0.5)) * 1e-3;
    state.counters["latency_p99_us"] = static_cast<double>(s.latency_quantile_ns(0.99)) * 1e-3;
    state.counters["latency_max_us"] = static_cast<double>(s.max_latency_ns) * 1e-3;
    state.counters["work_max_us"] = static_cast<double>(s.max_work_ns) * 1e-3;
  }
}
BENCHMARK(BM_PacedSilLoopPeriod)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
