// Cost of the floating capture per loop sample (FloatingCapture::on_sample: ring write,
// trigger evaluation, and during a capture the incremental copy into the event buffer), at
// the bath board's settings (0.5 s + 2 s at 10 kHz).
#include <benchmark/benchmark.h>

#include <array>
#include <vector>

#include "firmware/capture/floating_capture.hpp"

namespace {
using namespace amb::fw;

std::vector<LoopSample> samples(size_t n) {
  std::vector<LoopSample> v(n);
  for (size_t i = 0; i < n; ++i) {
    LoopSample& s = v[i];
    s.seq = i;
    s.t_ns = static_cast<int64_t>(i) * 100000;
    for (size_t k = 0; k < 4; ++k) {
      s.displacement_m[k] = 1e-5f * static_cast<float>((i * 7 + k) % 13);
      s.coil_current_a[k] = 0.1f * static_cast<float>((i + k) % 5);
      s.current_demand_a[k] = s.coil_current_a[k];
    }
    s.phase = 5;  // at_speed
    s.state = 3;  // running
    s.flags = flag_amplifiers_enabled | flag_levitated;
  }
  return v;
}

const std::array<double, 4> k_angles{45.0, -45.0, 45.0, -45.0};

/// Armed, no trigger: the steady-state cost every period.
void BM_CaptureOnSampleArmed(benchmark::State& state) {
  FloatingCapture c;
  c.configure(CaptureParams{}, k_angles, 10000.0);
  const auto v = samples(4096);
  size_t i = 0;
  for (auto _ : state) {
    c.on_sample(v[i & 4095]);
    ++i;
  }
  benchmark::DoNotOptimize(c.counters().samples);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CaptureOnSampleArmed);

/// Worst case: always capturing (the consumer releases each frozen event at once), so every
/// sample also copies itself and ceil(pre/post) pre-trigger samples into the event buffer.
void BM_CaptureOnSampleCapturing(benchmark::State& state) {
  CaptureParams p;
  p.rearm_hold_s = 0.0;
  FloatingCapture c;
  c.configure(p, k_angles, 10000.0);
  const auto v = samples(4096);
  size_t i = 0;
  for (auto _ : state) {
    if (c.mode() != FloatingCapture::Mode::capturing) {
      state.PauseTiming();
      if (const FrozenEvent* e = c.take()) c.release(e);
      c.request_manual_trigger();
      state.ResumeTiming();
    }
    c.on_sample(v[i & 4095]);
    ++i;
  }
  benchmark::DoNotOptimize(c.counters().events_frozen);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CaptureOnSampleCapturing);

}  // namespace
