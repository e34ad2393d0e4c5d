// Per-hop cost of the on-board speed-ridge tracker (seed 003 STFT settings).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "model/signal/speed_ridge_tracker.hpp"

namespace {
namespace sig = amb::model::signal;

std::vector<double> test_tone(double fs_hz, size_t n) {
  std::vector<double> x(n);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0.0, 0.3);
  for (size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / fs_hz;
    x[i] = std::sin(2 * std::numbers::pi * 100.0 * t) + 0.5 * std::sin(2 * std::numbers::pi * 200.0 * t) + g(rng);
  }
  return x;
}

// One hop = hop_samples() pushes, the last of which computes the frame, comb and Viterbi.
void BM_TrackerHop(benchmark::State& state) {
  // range(0): 1 = order-tracking warp with chirp-rate hypotheses (default; 5 FFTs per hop
  // while tracking), 0 = plain STFT (1 FFT per hop, seed 003).
  sig::SpeedTrackerOptions o;
  o.order_tracking = state.range(0) != 0;
  sig::SpeedRidgeTracker tr;
  if (!tr.configure(o).empty()) {
    state.SkipWithError("configure failed");
    return;
  }
  const size_t hop = o.stft.hop_samples();
  const auto x = test_tone(o.stft.sample_rate_hz, 20 * o.stft.window_samples());
  size_t i = 0;
  // Fill the first window so every iteration produces one update.
  for (; i < o.stft.window_samples() - 1; ++i) tr.push(x[i]);
  size_t updates = 0;
  for (auto _ : state) {
    for (size_t k = 0; k < hop; ++k) {
      updates += tr.push(x[i]) ? 1 : 0;
      if (++i == x.size()) i = o.stft.window_samples();
    }
  }
  benchmark::DoNotOptimize(updates);
  state.counters["hop_samples"] = static_cast<double>(hop);
  state.counters["tracking"] = tr.latest().lost ? 0.0 : 1.0;
  state.counters["updates_per_iter"] =
      static_cast<double>(updates) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_TrackerHop)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

}  // namespace
