#pragma once
// The host model of a steady-state record and its fit: the rig's closed loop (board file)
// with a set of model elements (model/effects/), compared with what extract_steady() found.
//
// Original unknowns, solved in closed form at every evaluation ("refitted together"):
//   * the sensor-noise variance sigma^2 (white, per sample; one for all sensors) and the
//     variance of a white force disturbance on every actuator axis,
//   * the unbalance: a complex forward-rotating 1x force at each of the two heaviest disks,
// The base model's uncertain parameters (EffectSet::update: loop delay, force scale) are
// counted as base parameters whether or not they were updated; fitted by the caller.
// And the linear parameters of the elements that have them (sensor_runout phasors,
// aux_bearing_offset). Nonlinear element parameters are fitted by the caller.
//
// Likelihood (negative log, up to constants):
//   PSD bands  Whittle: sum K (ln P + P^/P), P = sigma^2 sum_k |H_ck|^2 2/fs
//   lines      complex Gaussian, variance 2 P(h f)/T plus a 3 % model-error floor
//   statics    Gaussian, variance P(f_min)/T plus floors (0.2 um; 5e-4 of the current limit)
//   rest       Gaussian, variance std^2/N plus (0.5 um)^2
#include <array>
#include <complex>
#include <memory>
#include <vector>

#include "firmware/board/board.hpp"
#include "model/rig/rig_model.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "model/effects/effect_set.hpp"

namespace amb::host::residual {

/// Parameters of the base model: sensor noise, force noise, 2 complex unbalance forces,
/// loop delay, force scale.
inline constexpr int k_base_parameters = 8;

struct ErrorFigures {
  double rms = 0.0;       ///< sqrt(mean over channels of sum r^2 / sum y^2), time domain (steady window, and the rest segment), 1
  double spectral = 0.0;  ///< rms over channels and bands of 10 log10(P^/P_model), dB
  double pearson = 0.0;   ///< mean over channels of the Pearson correlation of log P^ and log P_model, 1
  double statics = 0.0;   ///< rms of the rest-position residuals (m) relative to the aux clearance, 1 (0 without rest)
};

struct SteadyEvaluation {
  model::effects::EffectSet effects;   ///< with the linear parameters filled in
  double nll = 0.0;
  int parameters = 0;                  ///< base (k_base_parameters) + element parameters
  int data_points = 0;                 ///< real data values used
  double bic = 0.0;                    ///< 2 nll + parameters ln(data_points)
  double aic = 0.0;                    ///< 2 nll + 2 parameters
  double noise_rms_m = 0.0;            ///< fitted sensor noise, m rms per sample
  double force_noise_rms_n = 0.0;      ///< fitted force disturbance per actuator axis, N rms per sample
  std::array<std::complex<double>, 2> unbalance_force_n{};  ///< fitted forward 1x forces at the two planes, N
  std::array<double, 2> unbalance_axial_m{};
  std::array<double, k_channels> static_pred{};
  std::array<std::array<std::complex<double>, k_orders>, k_channels> order_pred{};
  std::vector<std::array<double, k_channels>> psd_pred;  ///< per band
  std::array<double, 4> rest_pred_m{};
  std::array<double, 4> ki_ratio{};    ///< model's local ki ratio (saturation), 1
  ErrorFigures error;
};

/// Evaluate the model with `effects` (linear element parameters are fitted; their given
/// values are ignored). Throws std::invalid_argument for a model that cannot be built.
/// `known_runout` (optional): a sensor runout known from elsewhere (a drop event's contact
/// geometry, in the record's angle reference), held in the prediction of the speed-order lines
/// instead of fitted (ignored when `effects` has a runout of its own). `rig`: the board's rig
/// model built once by the caller (model/rig); null: built here.
SteadyEvaluation evaluate_steady(const SteadyData& d, const board::BoardConfig& b, const model::effects::EffectSet& effects,
                                 const model::effects::SensorRunout* known_runout = nullptr,
                                 const std::shared_ptr<const model::RigModel>& rig = nullptr);

/// Number of fitted parameters an element adds.
int element_parameters(model::effects::EffectKind k);

}  // namespace amb::host::residual
