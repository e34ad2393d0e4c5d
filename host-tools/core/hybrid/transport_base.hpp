#pragma once
// The measured-spectrum baselines of the hybrid model (issue 34): the training spectra of the
// same bearing state moved to the queried speed by the kinematic law (every bearing and shaft
// line at a fixed order of the shaft speed, seed 001 eq. 14-16; spectra.hpp), no learning.
//
//  - nearest: the training case of the state nearest in speed, moved to the queried speed;
//  - interpolated: the two training cases bracketing the queried speed, each moved to it, mixed
//    linearly in speed (weight (s - s_lo) / (s_hi - s_lo) on the upper one) in the spectrum's
//    domain (log10 PSD; envelope power). Outside the trained speed range there is no bracket:
//    the weights are clamped, so the interpolation is the nearest case (the two coincide);
//  - fixed: the interpolated mix of the same cases NOT moved (their lines at the measured
//    frequencies): what a line that does not follow the shaft speed (supply frequency,
//    structural resonance) would read. An input of the learned correction, not a baseline.
#include <string>
#include <vector>

#include "host-tools/core/hybrid/physics.hpp"

namespace amb::host::hybrid {

/// Mean measured spectra of one training case (state, operating point), in the maps' domains.
struct ReferenceSpectra {
  BearingState state = BearingState::healthy;
  OperatingPoint op;
  int segments = 0;
  std::vector<double> log_psd;    ///< mean log10 PSD of the segments
  std::vector<double> env_power;  ///< mean envelope power of the segments / measured_env_scale
};

/// One training case moved to the queried speed.
struct TransportSource {
  std::string case_name;        ///< "state@rpm/load"
  double weight = 1.0;          ///< its weight in the interpolation
  double speed_rpm = 0.0;       ///< the case's speed, rpm
  std::vector<double> moved_log_psd, moved_env_power;  ///< moved to the queried speed
  std::vector<double> log_psd, env_power;              ///< as measured (not moved)
};

/// The transported baselines of one query, on the model's grids.
struct TransportedBase {
  bool found = false;  ///< false: no training case of the state (every vector empty)
  std::string nearest_case, interp_cases;  ///< "state@rpm/load" of the case(s) used
  double upper_weight = 0.0;               ///< interpolation weight of the upper case (0 if one case)
  std::vector<double> nearest_log_psd, nearest_env_power;  ///< nearest case, moved
  std::vector<double> interp_log_psd, interp_env_power;    ///< bracketing cases, moved, mixed
  std::vector<double> fixed_log_psd, fixed_env_power;      ///< bracketing cases, not moved, mixed
  std::vector<TransportSource> sources;  ///< the case(s) of the interpolation (1 or 2), weights summing to 1
};

/// Every training case of `state` except those at `exclude` (same speed and load), each moved
/// to `op` with weight 1: the single-source transports the learned correction is trained on.
std::vector<TransportSource> all_sources(const std::vector<ReferenceSpectra>& refs, BearingState state, const OperatingPoint& op,
                                         const std::vector<double>& psd_hz, const std::vector<double>& env_hz,
                                         const std::vector<double>& scales, int halfwidth_bins, const OperatingPoint& exclude);

/// Build the baselines of `state` at `op` from `refs`. Cases at the operating point
/// `exclude` (same speed and load) are skipped when `exclude` is given (cross-fitting: a
/// training segment's input never comes from its own operating point). `psd_hz` / `env_hz`:
/// bin centres; `scales`: speed scales averaged over (speed_scales()); `halfwidth_bins`: the
/// local mean of the log PSD that stays in place (transport_log_psd()).
TransportedBase transported_base(const std::vector<ReferenceSpectra>& refs, BearingState state, const OperatingPoint& op,
                                 const std::vector<double>& psd_hz, const std::vector<double>& env_hz,
                                 const std::vector<double>& scales, int halfwidth_bins,
                                 const OperatingPoint* exclude = nullptr);

/// "state@rpm/load" of a case.
std::string case_name(BearingState s, const OperatingPoint& op);

}  // namespace amb::host::hybrid
