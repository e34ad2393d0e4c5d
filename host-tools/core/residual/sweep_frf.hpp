#pragma once
// The residual loop on a measured current-to-response sweep (the TUM MLPS record):
//  1. nonlinear stretches are detected from the time data (nonlinear_span.hpp) and left out;
//  2. H1 FRF from the control current (A) to each shaft accelerometer (m/s^2), Welch with Hann
//     segments, coherence per bin; a zero-padded estimate for the peak frequencies;
//  3. the compared band: fit band with coherence >= min_coherence per channel and bin;
//  4. the model is the one the rig measures with the current as reference: the rotor with the
//     excited bearing's current as input and the other bearing closed through its PID
//     (model/analysis/half_open_frf.hpp); which AMB was excited and the sign convention are
//     chosen by the data; accelerometer positions (not recorded) are fitted per channel;
//  5. FE model updating (frf_update.hpp): resonance peaks from the data (modal_peaks.hpp),
//     frequencies first, then the complex FRF (shapes and levels), bounded parameters, NLopt;
//     elements the board lacks (accelerometer masses "sensor_mass", actuator lag / loop delay
//     "amplifier_lag", a housing / foundation mode "pedestal_resonance") are added greedily
//     when they lower the BIC by more than min_delta_bic;
//  6. identifiability (Jacobian rank, correlations), modal frequencies and MAC per peak, and a
//     validation that fits half the accelerometers and checks the other half, both ways.
#include <array>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/residual/frf_update.hpp"
#include "host-tools/core/residual/nonlinear_span.hpp"
#include "host-tools/core/residual/residual_loop.hpp"

namespace amb::host::residual {

struct SweepFrf {
  std::vector<double> f_hz;
  std::vector<std::vector<std::complex<double>>> h;   ///< [channel][bin], (m/s^2)/A
  std::vector<std::vector<double>> coherence;         ///< [channel][bin]
  int segments = 0;                                   ///< segments averaged
};

struct SweepOptions {
  double segment_s = 1.0;                 ///< Welch segment, s
  int zero_pad = 1;                       ///< FFT length = zero_pad x segment (peak frequencies: 4)
  std::vector<std::array<double, 2>> exclude_spans_s;  ///< time spans left out of the FRF, s
  double f_min_hz = 8.0, f_max_hz = 240.0;///< compared band, Hz
  double min_coherence = 0.8;             ///< bins below this (per channel) are not compared
  double min_delta_bic = 10.0;            ///< an element must lower the BIC by more than this
  int max_evaluations = 400;              ///< per bounded fit (NLopt BOBYQA)
  bool validate = true;                   ///< run the half-channel validation
};

/// H1 estimate. `input`: excitation current (A); `outputs`: response channels (m/s^2).
SweepFrf estimate_frf(const std::vector<double>& input, const std::vector<std::vector<double>>& outputs, double fs_hz,
                      const SweepOptions& o);

struct SweepFitEvaluation {
  int excited_axis = 0;                   ///< actuator axis index of the excitation (0: AMB A x, 2: AMB B x)
  double gain_scale = 1.0;                ///< PID gains of the closed bearing relative to the board's, 1
  std::vector<double> accel_axial_m;      ///< fitted accelerometer positions, m
  double cost = 0.0;                      ///< coherence-weighted squared complex log error
  int parameters = 0, data_points = 0;
  double bic = 0.0;
  ErrorFigures error;                     ///< over the compared bins, unweighted: rms |ln ratio|, spectral rms dB, pearson of log|H|
  std::vector<std::vector<std::complex<double>>> h_model;  ///< [channel][bin of SweepOutcome::data]
};

struct ModeMatch {
  double measured_hz = 0.0, model_hz = 0.0;  ///< model_hz NaN: no model peak within +-4 %
  double error_pct = 0.0;                    ///< 100 (model / measured - 1)
  double mac = 0.0;                          ///< measured vs modelled shape over the accelerometers
  double prominence = 0.0;
};

struct ValidationRun {
  std::vector<size_t> fit_channels, check_channels;
  FrfErrors fit, check;                   ///< after the fit on fit_channels
  FrfErrors check_nominal;                ///< the board's model on the check channels
};

struct SweepOutcome {
  SweepFrf frf;
  FrfFitData data;                        ///< compared bins and weights
  std::vector<NonlinearSpan> nonlinear;
  SweepFitEvaluation before, after;
  std::vector<CandidateScore> ranking;
  std::vector<EffectAdded> effects_added;
  std::vector<UpdateParameter> parameters;  ///< final values (value), nominal, bounds
  std::vector<bool> parameter_at_bound;
  Identifiability identifiability;
  std::vector<ModeMatch> modes_before, modes_after;
  std::vector<ValidationRun> validation;
  std::vector<std::string> notes;         ///< structure of the residual
  std::string verdict;
};

/// The whole loop for an input/outputs record on `b`.
SweepOutcome run_sweep_residual(const std::vector<double>& input, const std::vector<std::vector<double>>& outputs,
                                double fs_hz, const board::BoardConfig& b, const SweepOptions& o = {});

}  // namespace amb::host::residual
