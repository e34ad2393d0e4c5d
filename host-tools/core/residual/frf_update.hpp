#pragma once
// FE model updating of the rotor-AMB model against a measured current-to-acceleration FRF
// (the TUM MLPS sweep), the way it is done in structural dynamics: physically bounded
// parameters of the board's own model (rotor stiffness per region, disk inertias, AMB
// negative stiffness and force gain with its lag, PID gain scale of the closed bearing,
// accelerometer mass, modal damping per bending mode, optionally a housing mode), fitted
// with NLopt (BOBYQA in normalised bounded coordinates) on the coherence-weighted complex
// log error; accelerometer positions (not recorded) are a per-channel nuisance fitted on a
// 2 mm grid inside every evaluation. Frequencies first (model peak frequencies against the
// measured peaks), then the full complex FRF (shapes and levels).
// Identifiability: finite-difference Jacobian of the weighted residuals in normalised
// coordinates, its singular values, and the correlation of the estimates.
// Model: model/analysis/half_open_frf.hpp (the FRF with the excited bearing's current as input).
#include <complex>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "model/analysis/half_open_frf.hpp"

namespace amb::host::residual {

/// The measured FRF restricted to what is fitted: bins and per channel/bin weights.
struct FrfFitData {
  std::vector<double> f_hz;                           ///< bin frequencies, Hz
  std::vector<std::vector<std::complex<double>>> h;   ///< [channel][bin], (m/s^2)/A
  std::vector<std::vector<double>> w;                 ///< [channel][bin] weight; 0: bin not used
};

/// One updating parameter with its physical bounds.
struct UpdateParameter {
  std::string name;        ///< e.g. "shaft_bending_scale"
  std::string unit;        ///< "1", "N/m", "N/A", "s", "kg"
  std::string meaning;     ///< what it is and why these bounds
  double nominal = 0.0;    ///< board / RIG.md value
  double lower = 0.0, upper = 0.0;  ///< physical bounds
  bool log_scale = false;  ///< optimise in log coordinates
  bool free = true;        ///< false: held at `value`
  double value = 0.0;      ///< current estimate
};

/// The parameterised model of one record.
struct UpdateModel {
  model::analysis::HalfOpenParams base;   ///< from the board
  std::vector<UpdateParameter> p;
  std::vector<size_t> shaft_elements, zone_elements;  ///< element indices per stiffness region
  size_t centre_disk = 0;                 ///< heaviest disk (the disc)
  std::vector<double> mass_axial_m;       ///< where the accelerometer masses sit, m
  double sign = 1.0;                      ///< +1 / -1: sign convention of current vs acceleration
  bool housing = false;                   ///< housing-mode parameters in use (element "pedestal_resonance")
  bool sensor_mass = false;               ///< accelerometer masses in the model (element "sensor_mass")
  bool lag = true;                        ///< current-amplifier lag in the closed loop (held at the board's bandwidth)
  bool fixed_positions = false;           ///< evaluate at mass_axial_m instead of searching each accelerometer's position
  int housing_bearing = 1;                ///< bearing carrying the housing mode
  double current_channel = 1.0;           ///< measured A per A of control current (1: the control current; 2: the
                                          ///< difference of the axis' two coil currents, i0 + i and i0 - i)
  bool coupling = false;                  ///< drive coupling hub on a shaft end (element "drive_coupling")
  double coupling_axial_m = 0.0;          ///< where the coupling sits (a shaft end), m
  bool eddy = false;                      ///< eddy currents in the AMB magnetic circuits (element "eddy_current_lag")
  bool resonator = false;                 ///< a flexibly attached part (element "attached_resonator")
  double resonator_axial_m = 0.0;         ///< where it is attached, m
};

/// Builds the parameter list from the board (nominal values and bounds: see the .cpp table).
UpdateModel make_update_model(const board::BoardConfig& b, int excited_bearing, size_t channels);

/// True when the model has a parameter of that name.
bool has_parameter(const UpdateModel& m, const std::string& name);

/// The element a parameter belongs to ("" for the board's own parameters).
std::string element_of(const std::string& parameter);

/// Add the accelerometer mass (one value for all, at mass_axial_m).
void add_sensor_mass(UpdateModel& m, double mass_kg);

/// Free the current amplifier's lag (held at the board's bandwidth by make_update_model).
void free_amplifier_lag(UpdateModel& m);

/// Add the housing-mode parameters (mass, frequency, damping ratio) at `bearing`.
void add_housing(UpdateModel& m, int bearing, double frequency_hz, double mass_kg, double damping_ratio);

/// Add the drive-coupling mass at the shaft end `axial_m` (a point mass: its diametral inertia is
/// not separable from the mass in the data, correlation -0.99).
void add_coupling(UpdateModel& m, double axial_m, double mass_kg);

/// Add the eddy-current time constant of both AMBs (solid-iron, half-order model).
void add_eddy(UpdateModel& m, double time_s);

/// Add a resonator (position, mass, frequency, damping ratio), starting at `axial_m`.
void add_resonator(UpdateModel& m, double axial_m, double mass_kg, double frequency_hz, double damping_ratio);

/// The model parameters for given parameter values.
model::analysis::HalfOpenParams to_model(const UpdateModel& m, const std::vector<double>& values);

struct FrfFit {
  std::vector<double> values;               ///< parameter values (UpdateModel::p order)
  std::vector<size_t> channels;             ///< channels this fit used
  std::vector<double> accel_axial_m;        ///< fitted position per channel (all channels), m
  double cost = 0.0;                        ///< sum w |ln(H_meas / H_model)|^2 over used channels
  int evaluations = 0;
  std::vector<std::vector<std::complex<double>>> h_model;  ///< [channel][bin] at the fitted positions
};

/// Evaluate the model: positions fitted per channel (all channels), cost over `channels`.
FrfFit evaluate_fit(const UpdateModel& m, const std::vector<double>& values, const FrfFitData& d,
                    const std::vector<size_t>& channels);

/// Bounded fit of the free parameters on `channels` (NLopt BOBYQA), from `start`.
FrfFit fit_parameters(const UpdateModel& m, const std::vector<double>& start, const FrfFitData& d,
                      const std::vector<size_t>& channels, int max_evaluations);

/// "Frequencies first": fit the free parameters so that the model's FRF peaks (summed over
/// the positions in `accel_axial_m`) fall on `measured_hz`. Returns the values.
std::vector<double> fit_frequencies(const UpdateModel& m, const std::vector<double>& start,
                                    const std::vector<double>& measured_hz, const std::vector<double>& accel_axial_m,
                                    int max_evaluations, const std::vector<double>& channel_norms = {});

/// Model peak frequency near each measured one (+-4 %), from the same indicator as the measured
/// peaks: sum over the positions of |acceleration|^2 / channel_norms[c] (empty: 1); NaN where
/// the window has no interior maximum.
std::vector<double> model_peaks(const model::analysis::HalfOpenFrf& f, const std::vector<double>& measured_hz,
                                const std::vector<double>& axial_m, const std::vector<double>& channel_norms = {});

/// Error figures over the used bins of `channels`, each bin counted once (unweighted):
/// spectral = rms of 20 log10 |H_meas / H_model| (dB); pearson = mean over channels of the
/// correlation of log |H|; rms = rms |ln(H_meas / H_model)| (complex, incl. phase).
struct FrfErrors {
  double spectral_db = 0.0, pearson = 0.0, rms_ln = 0.0;
  int bins = 0;
};
FrfErrors frf_errors(const FrfFitData& d, const std::vector<std::vector<std::complex<double>>>& h_model,
                     const std::vector<size_t>& channels);

struct Identifiability {
  std::vector<std::string> names;            ///< free parameters
  std::vector<double> singular_values;       ///< of the weighted Jacobian (normalised coords), descending
  int rank = 0;                              ///< singular values above 1e-4 of the largest
  double condition = 0.0;
  std::vector<std::vector<double>> correlation;  ///< of the estimates, free x free
  std::vector<double> std_normalised;        ///< 1-sigma of each estimate in normalised units (0..1 = bounds)
  /// Per free parameter, 0..1: its share in the unidentified directions (sum of the squared
  /// right-singular-vector components over the singular values at or below the rank
  /// threshold); 0 when the Jacobian has full rank.
  std::vector<double> null_share;
  std::vector<std::string> notes;            ///< strongly correlated pairs
};
Identifiability identifiability(const UpdateModel& m, const FrfFit& fit, const FrfFitData& d);

/// True when a free parameter lies within 1 % of its range of a bound.
bool at_bound(const UpdateParameter& p, double value);

}  // namespace amb::host::residual
