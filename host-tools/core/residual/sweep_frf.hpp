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
//  5. FE model updating (frf_update.hpp) of the board's own parameters first (rotor stiffness
//     per region, inertias, ks, ki, PID, loop delay, modal damping), with the current channel
//     read as the control current or as the difference of the axis' two coil currents (the
//     data choose; RIG.md: which current "Point10" is, is not recorded); resonance peaks from
//     the data (modal_peaks.hpp), frequencies first, then the complex FRF;
//  6. elements real rigs have, each with physical bounds, added one at a time (forward
//     selection): the candidate that lowers the BIC most is refitted with everything free and
//     kept when the BIC falls by more than min_delta_bic, the misfit by min_relative_improvement,
//     none of its parameters ends on a bound (a parameter on a bound means the element is not
//     what the data show) and the model stays identifiable (no own parameter correlated >= 0.99
//     with another; the Jacobian loses no rank to it: a new deficit counts against the element
//     when its own parameters make up most of the unidentified directions). Candidates:
//     accelerometer masses "sensor_mass", the current-amplifier lag freed "amplifier_lag" (held
//     at the board's bandwidth otherwise), eddy currents
//     in the AMB iron "eddy_current_lag", a drive coupling on either shaft end
//     "drive_coupling", a flexibly attached part anywhere on the shaft "attached_resonator", a
//     housing / foundation mode at either AMB "pedestal_resonance";
//  7. identifiability (Jacobian rank, correlations), modal frequencies and MAC per peak (model
//     peaks from the same indicator as the measured ones), a validation that fits half the
//     accelerometers and checks the other half, both ways, and one on the other record type:
//     the excited bearing's current per sweep voltage (I/V), predicted from the controller the
//     acceleration FRFs identified (only the injection gain fitted).
#include <array>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "host-tools/core/residual/engine/criterion.hpp"

#include "firmware/board/board.hpp"
#include "host-tools/core/residual/frf_update.hpp"
#include "host-tools/core/residual/nonlinear_span.hpp"
#include "host-tools/core/residual/residual_loop.hpp"

namespace amb::host::residual {

/// The TUM sweep pair (Sweep_Time_Anregung.mat / Sweep_Time_Ausgang.mat) in SI units. Test.Lab
/// stores every channel in MKS ("Data saved by Test.Lab in MKS"); a channel's
/// unit_transformation only converts to its display unit (the accelerometers: factor
/// 1/9.80665 for g), so the stored accelerations are m/s^2 and are used as they are.
struct TumSweep {
  std::vector<double> current_a;                 ///< "Point10:+X", A
  std::vector<double> command_v;                 ///< the 1 V sine-sweep command ("Welle:1:-X", V)
  std::vector<std::vector<double>> accel_m_s2;   ///< "Welle:1..8:+X", m/s^2
  double fs_hz = 0.0;
  double accel_display_factor = 1.0;             ///< display unit per SI unit of the accelerometers (1/9.80665: g)
};

/// Reads the pair from `dir`. Throws std::runtime_error (naming the file) when it cannot.
TumSweep read_tum_sweep(const std::string& dir);

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
  /// The one keep/reject criterion (engine/criterion.hpp). The decision feature is the
  /// coherence-weighted misfit: its weights are the FRF estimator's noise, the misfit is mostly
  /// model error, so the BIC alone overstates small gains and the misfit must also fall by
  /// criterion.min_relative_improvement.
  engine::Criterion criterion;
  /// Per bounded fit (NLopt BOBYQA). The fits stop on this budget, not on convergence, and the
  /// forward selection is path-dependent: docs/residual.md (TUM section) gives what another
  /// budget does. The command and the test use this default.
  int max_evaluations = 300;
  int screen_evaluations = 250;           ///< per candidate screening fit (accelerometer positions held)
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

/// One measured resonance against the model, two ways: (a) peaks of the same indicator
/// (modal_peaks.hpp) on the measured and the modelled FRF, MAC of the FRFs at the peaks;
/// (b) experimental modal analysis (fit_modes) applied alike to both FRFs over the band around
/// the peak (close peaks share a band): pole frequencies, damping ratios and the MAC of the
/// residue vectors (mode shapes).
struct ModeMatch {
  double measured_hz = 0.0, model_hz = 0.0;  ///< peaks; model_hz NaN: no model peak within +-4 %
  double error_pct = 0.0;                    ///< 100 (model / measured - 1)
  double mac = 0.0;                          ///< measured vs modelled FRF shape at the peaks
  double prominence = 0.0;
  double ema_measured_hz = 0.0, ema_model_hz = 0.0;        ///< pole frequencies, Hz (NaN: no fit)
  double ema_measured_zeta = 0.0, ema_model_zeta = 0.0;    ///< damping ratios, 1
  double ema_error_pct = 0.0;                              ///< 100 (model / measured - 1)
  double ema_mac = 0.0;                                    ///< residue shapes
};

struct ValidationRun {
  std::vector<size_t> fit_channels, check_channels;
  FrfErrors fit, check;                   ///< after the fit on fit_channels
  FrfErrors check_nominal;                ///< the board's model on the check channels
  std::vector<std::vector<std::complex<double>>> h_model;  ///< [channel][bin] of that fit (all channels)
};

/// Current per sweep voltage of the excited bearing (the sweep enters that bearing's loop):
/// measured and predicted from the updated model, I/V = g A / (1 + K H A) with K the closed
/// bearing's controller (same gains on both bearings), H the excited bearing's collocated
/// displacement per measured ampere, A the amplifier lag; only the real injection gain g is
/// fitted (closed form).
struct CurrentLoopCheck {
  bool done = false;
  std::vector<double> f_hz;
  std::vector<std::complex<double>> measured, model;   ///< A/V
  std::vector<bool> compared;                          ///< coherence >= min_coherence, outside excluded bins
  double gain = 0.0;                                   ///< injection gain g, A/V
  FrfErrors error, error_board;                        ///< updated model / the board's model (own gain fitted)
};

struct SweepOutcome {
  SweepFrf frf;
  FrfFitData data;                        ///< compared bins and weights
  std::vector<NonlinearSpan> nonlinear;
  SweepFitEvaluation before, updated, after;  ///< board model; board's own parameters updated; with the elements
  double current_channel = 1.0;           ///< measured A per A of control current chosen by the data
  std::vector<std::string> channel_evidence;  ///< both readings of the current channel, with their figures
  std::vector<CandidateScore> ranking;    ///< every candidate tried, in the order tried, with its outcome
  std::vector<EffectAdded> effects_added;
  std::vector<UpdateParameter> parameters;  ///< final values (value), nominal, bounds
  std::vector<bool> parameter_at_bound;
  Identifiability identifiability;
  std::vector<ModeMatch> modes_before, modes_after;
  std::vector<ValidationRun> validation;
  CurrentLoopCheck current_loop;
  std::vector<std::string> notes;         ///< structure of the residual
  std::string verdict;
};

/// The whole loop for an input/outputs record on `b`. `command_v` (optional, same length): the
/// sweep command, for the current-loop check.
SweepOutcome run_sweep_residual(const std::vector<double>& input, const std::vector<std::vector<double>>& outputs,
                                double fs_hz, const board::BoardConfig& b, const SweepOptions& o = {},
                                const std::vector<double>& command_v = {});

}  // namespace amb::host::residual
