#pragma once
// Test signals for the speed tracker: seed 003's five-phase speed profile and a synthetic
// "machine" (shaft harmonics + a bearing line + white noise) driven by any speed profile.
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

namespace amb::test {

/// Seed 003 five-phase profile, shaft speed in Hz: 0 -> 4000 rpm in 2 s, cruise to 7 s,
/// accelerate to max_rpm by 12 s, cruise to 20 s, brake to 0 by 23 s (linear ramps).
inline double five_phase_speed_hz(double t_s, double max_rpm) {
  const double low = 4000.0 / 60.0, high = max_rpm / 60.0;
  if (t_s <= 0.0) return 0.0;
  if (t_s < 2.0) return low * t_s / 2.0;
  if (t_s < 7.0) return low;
  if (t_s < 12.0) return low + (high - low) * (t_s - 7.0) / 5.0;
  if (t_s < 20.0) return high;
  if (t_s < 23.0) return high * (23.0 - t_s) / 3.0;
  return 0.0;
}

/// One line of the synthetic machine: order (multiple of shaft speed) and amplitude that
/// grows with speed as amplitude * (f / f_ref)^exponent.
struct SyntheticLine {
  double order = 1.0;
  double amplitude = 1.0;
  double exponent = 0.0;
};

/// Synthetic accelerometer signal: sum of lines at orders of the integrated shaft phase,
/// plus white Gaussian noise of rms `noise_rms`. Deterministic for a given seed.
inline std::vector<double> synthetic_machine(const std::function<double(double)>& speed_hz,
                                             const std::vector<SyntheticLine>& lines,
                                             double fs_hz, double duration_s, double noise_rms,
                                             uint64_t seed, double f_ref_hz = 100.0) {
  const size_t n = static_cast<size_t>(std::llround(duration_s * fs_hz));
  std::vector<double> x(n, 0.0);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise_rms);
  double phase_rev = 0.0;  // shaft angle, revolutions
  for (size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / fs_hz;
    const double f = speed_hz(t);
    double v = 0.0;
    for (size_t k = 0; k < lines.size(); ++k) {
      const SyntheticLine& l = lines[k];
      const double a = l.amplitude * std::pow(std::max(f, 0.0) / f_ref_hz, l.exponent);
      v += a * std::sin(2.0 * std::numbers::pi * l.order * phase_rev + 0.7 * static_cast<double>(k));
    }
    x[i] = v + gauss(rng);
    // Trapezoidal phase integration.
    phase_rev += 0.5 * (f + speed_hz(t + 1.0 / fs_hz)) / fs_hz;
  }
  return x;
}

}  // namespace amb::test
