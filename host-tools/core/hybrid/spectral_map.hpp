#pragma once
// The learned part of the hybrid model (seed 001 section 3.3, "data mapping"): a map from the
// condition (bearing state, operating point) and, for the hybrid, the physics model's spectrum
// to the measured spectrum, bin by bin in the log domain.
//
//   y_k = sum_t T_t(k) [ a_t + c_t . z + d_t . u ]          (transfer path, state, operating point)
//       + sum_b B_b(k) (g_b + G_b z + H_b u) . q_k          (physics; hybrid only)
//
// z: state one-hot (4); u: operating point (speed, load), standardised on the training set;
// q_k: physics features at bin k (local mean of the log level, line prominence = level - local mean);
// T_t: narrow hat functions over the grid's bin index (transfer_spacing_bins apart: on the
// constant-percentage part of the grid, spacing x rel_bin_width relative bandwidth, i.e. the
// width of a damped housing resonance); B_b: a few wide hats (`bands`) for the physics gains.
// Both are partitions of unity. Nothing is per bin: a per-bin weight can only memorise the
// training spectra line by line, which at another speed puts every speed-locked line at the
// training frequency. The physics weights are shared across the bins of a band: a line the
// physics places at a new frequency (another speed) is mapped by the same gain as the
// training lines near it. That is what lets the map carry over to a speed it was not trained
// at. The data-only map has the same transfer terms (it can learn a smooth spectrum per state
// and operating point) but no physics to place lines.
//
// Ridge regression with two penalties (transfer and physics weights), solved exactly
// (Eigen LDLT on the normal equations): deterministic, no iteration, no random start.
// data_only = the same map without the physics term (seed 001's "data-driven" baseline).
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace amb::host::hybrid {

inline constexpr int k_condition_states = 4;
inline constexpr int k_op_inputs = 2;        ///< speed, load
inline constexpr int k_physics_features = 2;  ///< per physics channel: local mean, prominence (level minus local mean)

struct SpectralMapOptions {
  bool use_physics = true;          ///< false: the data-only baseline
  int bands = 8;                    ///< wide hats over the grid for the physics gains (>= 1)
  int transfer_spacing_bins = 6;    ///< spacing of the narrow transfer-path hats, grid bins (>= 1)
  int local_halfwidth_bins = 3;     ///< local mean of the physics spectrum over +-this many bins
  double lambda_transfer = 1.0;     ///< ridge penalty of the state / operating-point transfer weights (a_t excluded)
  double lambda_physics = 1.0;      ///< ridge penalty of the physics weights, dimensionless
  bool state_gain = true;           ///< physics gain depends on the state (G_b)
  bool op_gain = true;              ///< physics gain depends on the operating point (H_b)
  int physics_channels = 1;         ///< number of physics spectra per case (>= 1)
  /// Split each physics spectrum into its local mean and the prominence above it (two gains:
  /// broadband level and lines). Off: the spectrum itself is the one feature.
  bool split_local = true;
  bool valid(std::string* why = nullptr) const;
};

/// One training or prediction case: the condition and, for the hybrid, the physics spectrum.
struct MapInput {
  int state = 0;                          ///< 0..3 (BearingState)
  std::array<double, k_op_inputs> op{};   ///< speed rpm, load
  /// Physics spectra on the grid (hybrid only), one per channel (e.g. the state's simulation and
  /// the healthy machine's at the same operating point), in the map's domain.
  std::vector<std::vector<double>> physics;
};

/// The trained map.
class SpectralMap {
 public:
  /// Fit on cases `in` with log-domain targets `y` (one row per case, grid bins as columns).
  /// `grid_hz`: bin centres (for the bands). Throws std::invalid_argument on inconsistent input.
  void train(const std::vector<MapInput>& in, const std::vector<std::vector<double>>& y,
             const std::vector<double>& grid_hz, const SpectralMapOptions& o);
  /// Predicted log-domain spectrum for one case.
  std::vector<double> predict(const MapInput& in) const;
  bool trained() const { return bins_ > 0; }
  size_t bins() const { return bins_; }
  nlohmann::json to_json() const;
  static SpectralMap from_json(const nlohmann::json& j);
  const SpectralMapOptions& options() const { return o_; }
  /// Root-mean-square training residual (log units).
  double training_rms() const { return training_rms_; }

 private:
  void physics_features(const std::vector<std::vector<double>>& q, std::vector<std::vector<double>>& out) const;
  size_t per_channel() const { return o_.split_local ? k_physics_features : 1; }
  size_t features() const { return o_.use_physics ? static_cast<size_t>(o_.physics_channels) * per_channel() : 0; }
  size_t transfer_count() const;  // unknowns per transfer hat
  size_t physics_count() const;   // unknowns per physics band
  size_t unknowns() const;
  // Sparse row of case `in` at bin k: (index, value) pairs appended to idx/val.
  void row(const MapInput& in, const std::vector<double>& q, size_t k, std::vector<long>& idx,
           std::vector<double>& val) const;

  SpectralMapOptions o_{};
  size_t bins_ = 0;
  std::vector<double> grid_hz_;
  size_t hats_ = 0;  // transfer hats
  std::array<double, k_op_inputs> op_mean_{}, op_scale_{};  // scale 0: input constant in training (ignored)
  std::vector<double> q_mean_, q_scale_;  // per physics feature
  std::vector<double> w_;  // [transfer hats x transfer_count | bands x physics_count]
  double training_rms_ = 0.0;
};

}  // namespace amb::host::hybrid
