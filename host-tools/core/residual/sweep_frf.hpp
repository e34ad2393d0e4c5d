#pragma once
// The residual loop on a measured current-to-response sweep (the TUM MLPS record):
//  * H1 FRF estimate from the AMB control current (A) to each shaft accelerometer (m/s^2),
//    Welch with Hann segments, segments that overlap an excluded time span (the nonlinear
//    burst) left out, and the coherence per bin;
//  * the host model: the board's closed loop at standstill (EffectLoopModel), FRF =
//    acceleration at z_c per actual current at the excited actuator axis;
//  * original unknowns: which AMB was excited, a scale on the PID gains (the gain set in use
//    is not recorded) and each accelerometer's axial position (not recorded);
//  * cost: coherence-weighted squared complex log error, sum_c,f w |ln(H_meas / H_model)|^2,
//    w = K g^2 / (1 - g^2) (K segments), over the fitted band less the excluded band;
//  * then the same loop as for steady records: rank the candidate elements by BIC, add the
//    top one, refit all, keep it if the BIC falls by more than min_delta_bic.
#include <array>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "model/effects/effect_set.hpp"

namespace amb::host::residual {

struct SweepFrf {
  std::vector<double> f_hz;
  std::vector<std::vector<std::complex<double>>> h;   ///< [channel][bin], (m/s^2)/A
  std::vector<std::vector<double>> coherence;         ///< [channel][bin]
  int segments = 0;                                   ///< segments averaged
};

struct SweepOptions {
  double segment_s = 1.0;                 ///< Welch segment, s
  double exclude_t0_s = 1.6, exclude_t1_s = 2.1;   ///< time span left out (nonlinear burst), s
  double f_min_hz = 8.0, f_max_hz = 240.0;          ///< fitted band, Hz
  double exclude_f0_hz = 50.0, exclude_f1_hz = 65.0;///< band left out of the fit, Hz
  double min_delta_bic = 10.0;
  int max_effects = 2;
  int max_evaluations = 60;
};

/// H1 estimate. `input`: excitation current (A); `outputs`: response channels (m/s^2).
SweepFrf estimate_frf(const std::vector<double>& input, const std::vector<std::vector<double>>& outputs, double fs_hz,
                      const SweepOptions& o);

struct SweepFitEvaluation {
  model::effects::EffectSet effects;
  int excited_axis = 0;                   ///< actuator axis index of the excitation (0: AMB A x, 2: AMB B x)
  double gain_scale = 1.0;                ///< PID gains relative to the board's, 1
  std::vector<double> accel_axial_m;      ///< fitted accelerometer positions, m
  double cost = 0.0;                      ///< weighted squared log error (= 2 nll)
  int parameters = 0, data_points = 0;
  double bic = 0.0;
  ErrorFigures error;                     ///< rms: rms over channels/bins of |ln ratio| (weighted 1); spectral: rms dB of |H| ratio; pearson: of log|H|
  std::vector<std::vector<std::complex<double>>> h_model;  ///< [channel][bin]
};

struct SweepOutcome {
  SweepFrf frf;
  SweepFitEvaluation before, after;
  std::vector<CandidateScore> ranking;
  std::vector<EffectAdded> effects_added;
  std::vector<std::string> notes;         ///< structure of the residual
  std::string verdict;
};

/// The whole loop for an input/outputs record on `b`.
SweepOutcome run_sweep_residual(const std::vector<double>& input, const std::vector<std::vector<double>>& outputs,
                                double fs_hz, const board::BoardConfig& b, const SweepOptions& o = {});

}  // namespace amb::host::residual
