// The loop's own delay on the linux-style loop (issue 38): CLOCK_MONOTONIC absolute sleeps,
// SCHED_FIFO 80 when permitted, the board's supervisor and controller, a front end that reads
// a fixed sample and writes nowhere. Per period the loop stamps sample instant (deadline) ->
// sample read -> step done -> demand written (LoopStats); reported: the delay's p50, p99,
// p99.9 and max in us and, at p50/p99, in loop periods (what the board key
// controller.loop_delay_periods is set from; docs/plant.md "Loop delay"). Run:
//   build/tests/bench/amb-bench --benchmark_filter=LoopDelay
// AMB_BENCH_LOOP_S sets the seconds per case (default 3).
#include <benchmark/benchmark.h>
#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cstdlib>
#include <thread>

#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "tests/bench/mono_clock.hpp"

namespace {

using namespace amb;

class FixedFrontEnd final : public hal::AnalogFrontEnd {
 public:
  bool read(hal::AnalogInputs& in) override {
    in.t_ns = bench::mono_ns();
    in.displacement_m = {1e-6f, -1e-6f, 0.5e-6f, 0.0f};
    in.tach_speed_hz = -1.0;
    return true;
  }
  void write(const hal::AnalogOutputs& out) override { last_ = out.current_demand_a[0]; }
  double last_ = 0.0;
};

class QuietDio final : public hal::DiscreteIo {
 public:
  hal::DiscreteInputs read() override { return {}; }
  void write(const hal::DiscreteOutputs&) override {}
};

void BM_LoopDelay(benchmark::State& state, const char* board_name) {
  const char* env = std::getenv("AMB_BENCH_LOOP_S");
  const double seconds = env ? std::atof(env) : 3.0;
  const board::BoardConfig b = board::load_board(board_name);
  fw::Supervisor sup;
  sup.configure(b);
  sup.post(fw::Command::levitate);  // the controller runs (energised) once the lift-off starts
  bench::MonoClock clock;
  FixedFrontEnd afe;
  QuietDio dio;
  fw::LoopRunner loop(clock, afe, dio, sup);
  const auto periods = static_cast<uint64_t>(seconds * b.rate_hz);
  bool fifo = false;
  for (auto _ : state) {
    std::thread t([&] {
      sched_param sp{};
      sp.sched_priority = 80;
      fifo = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &sp) == 0;
      loop.run_periods(periods);
    });
    t.join();
    state.SetIterationTime(seconds);
  }
  const fw::LoopStats& ls = loop.stats();
  const double per_period = b.rate_hz * 1e-9;
  state.counters["delay_p50_us"] = static_cast<double>(ls.delay_quantile_ns(0.5)) * 1e-3;
  state.counters["delay_p99_us"] = static_cast<double>(ls.delay_quantile_ns(0.99)) * 1e-3;
  state.counters["delay_p999_us"] = static_cast<double>(ls.delay_quantile_ns(0.999)) * 1e-3;
  state.counters["delay_max_us"] = static_cast<double>(ls.max_delay_ns) * 1e-3;
  state.counters["delay_p50_periods"] = static_cast<double>(ls.delay_quantile_ns(0.5)) * per_period;
  state.counters["delay_p99_periods"] = static_cast<double>(ls.delay_quantile_ns(0.99)) * per_period;
  state.counters["wake_p99_us"] = static_cast<double>(ls.latency_quantile_ns(0.99)) * 1e-3;
  state.counters["step_max_us"] = static_cast<double>(ls.max_step_ns) * 1e-3;
  state.counters["overruns"] = static_cast<double>(ls.overruns);
  state.counters["sched_fifo"] = fifo ? 1.0 : 0.0;
}

BENCHMARK_CAPTURE(BM_LoopDelay, bath, "bath-amb-rig")->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK_CAPTURE(BM_LoopDelay, unicamp, "unicamp-amb-rig")->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
