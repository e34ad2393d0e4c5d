#pragma once
// Settings of the loop-sensitivity sweep (ISO 14839-3), the board file's optional [sweep] table
// (parser: firmware/board/parse_sweep.cpp; docs/sweep.md "Board side"). Pure data with
// defaults: a board file without the table gets these values with the period, band and abort
// radius fitted to its rate and rig (board::sweep_defaults); they suit the 10 kHz reference
// rigs (Bath; Unicamp raises the amplitude) and the slow emulated board sets its own.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace amb::fw {

struct SweepParams {
  bool enabled = true;                 ///< false: every start is refused (reason not_configured)
  /// N: loop samples per excitation period; the lines sit at exact bins k * rate_hz / N.
  /// Default (board without the key): rate_hz, a 1 s period with 1 Hz bins.
  uint32_t samples_per_period = 10000;
  double f_min_hz = 2.0;               ///< lowest excited line, Hz (rounded up to a bin, >= bin 1)
  double f_max_hz = 1000.0;            ///< highest excited line, Hz (rounded down to a bin, < rate / 2; default at most 0.4 x rate)
  uint32_t lines = 60;                 ///< excited lines, log-spaced bins between f_min and f_max (fewer if bins run out)
  uint32_t settle_periods = 1;         ///< periods played per axis before recording (transient, not stored)
  uint32_t recorded_periods = 6;       ///< P: periods recorded per axis
  /// Peak of the excitation as a fraction of the AMB bias current (plane A's, rig.amb[0]).
  double amplitude_fraction = 0.05;
  /// Board limit of amplitude_fraction: a larger amplitude is refused (at load and at start).
  double amplitude_limit_fraction = 0.25;
  /// The sweep aborts (plain control, no fault) when the orbit radius at a sensor plane passes
  /// this fraction of the smaller aux-bearing clearance.
  double abort_clearance_fraction = 0.5;
  std::array<bool, 4> axes{true, true, true, true};  ///< control axes swept, in order 0..3 [A1, A2, B1, B2]
  uint32_t axis_count() const {
    uint32_t n = 0;
    for (bool a : axes) n += a ? 1u : 0u;
    return n;
  }
};

/// The DFT bins of an N-sample period at `rate_hz` inside [f_min_hz, f_max_hz]: [lo, hi]
/// (lo >= 1, hi < N / 2); hi < lo when the band holds none.
struct BinRange {
  uint32_t lo = 1, hi = 0;
};
inline BinRange sweep_bin_range(double rate_hz, uint32_t samples_per_period, double f_min_hz, double f_max_hz) {
  BinRange b;
  if (samples_per_period < 4 || !(rate_hz > 0.0)) return b;
  const double df = rate_hz / static_cast<double>(samples_per_period);
  b.lo = static_cast<uint32_t>(std::max(1.0, std::ceil(f_min_hz / df - 1e-9)));
  b.hi = static_cast<uint32_t>(std::max(0.0, std::min(std::floor(f_max_hz / df + 1e-9), static_cast<double>((samples_per_period - 1) / 2))));
  return b;
}

}  // namespace amb::fw
