#pragma once
// Test data for the host's sweep analysis without the board's generator: the simulated rig
// (the board's penalty-contact rotor-AMB plant on the sim backend, sensor noise on) closed by
// the firmware's own controller pieces (PidAxis per direction, AxisTransform), as
// tests/sil/loop_delay_test.cpp does; a multisine e (Schroeder phases, lines at exact bins of
// the period) is added to one axis' demand before the plant, axis after axis, and e, u_c,
// u = u_c + e and the axis' position reading are recorded into a SweepRecord
// (host-tools/core/sweep/sweep_record.hpp). Model elements can be put into the simulated plant
// (model/effects/effect_plant.hpp); the record does not say which.
#include <cstdint>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/sweep/sweep_record.hpp"
#include "model/effects/effect_set.hpp"

namespace amb::test {

struct SilSweepOptions {
  model::effects::EffectSet effects;  ///< put into the simulated plant only
  std::uint64_t seed = 1;             ///< sensor-noise seed
  double amplitude_fraction = 0.05;   ///< peak of e / the bias current (the default amplitude)
  std::vector<int> axes{0, 1, 2, 3};
  int samples_per_period = 5000;      ///< N (10 kHz: 0.5 s, 2 Hz line spacing)
  int settle_periods = 2;
  int recorded_periods = 8;
  double f_lo_hz = 2.0, f_hi_hz = 1000.0;   ///< swept band
  int lines = 48;                     ///< log-spaced, rounded to distinct bins
  double noise_scale = 1.0;           ///< sensor noise relative to the board's
  bool stepped = false;               ///< stepped sine: one line per step (same lines)
};

/// Runs the sweep on the board's simulated rig. Throws std::runtime_error if the rotor leaves
/// the levitated range.
host::sweep::SweepRecord run_sil_sweep(const board::BoardConfig& b, const SilSweepOptions& o);

/// The multisine of one period: lines at `bins`, equal amplitude, Schroeder phases, scaled to
/// peak `amplitude_a`; returns the samples and its crest factor (peak / rms).
std::vector<double> multisine(int samples_per_period, const std::vector<int>& bins, double amplitude_a, double& crest_factor);

}  // namespace amb::test
