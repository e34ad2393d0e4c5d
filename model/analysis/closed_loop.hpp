#pragma once
// Linearised closed loop of a rig at a given spin speed (host/analysis side; allocates):
//   rotor (modally reduced, gyroscopic, Rayleigh damping)
//   + AMBs linearised at the centre (F = ks z + ki i per actuator axis, at +-45 deg)
//   + sensors at their own planes and angles with first-order roll-off
//   + first-order current amplifier per actuator axis
//   + per bearing plane: sensors -> (x, y), a PID per direction in the form of seed 002 eq. 19,
//     F = -(KP e + KI \int e + KD de/dt) with a filtered derivative, the notches, (Fx, Fy) ->
//     actuator axes, i = f / ki.
// Two controller forms:
//   * continuous (sample_rate_hz == 0): analog PID, derivative s/(1 + s/wf), notches
//     (s^2 + depth*BW s + w0^2) / (s^2 + BW s + w0^2); no delay;
//   * sampled (sample_rate_hz > 0): the firmware's own difference equations (PidAxis: filtered
//     backward difference, forward-Euler integrator, Tustin notches with a pre-warped centre;
//     AxisTransform), the sensors sampled at the period, the demand held (zero-order hold) and
//     applied `loop_delay_periods` after the sample instant (computation and transport). The
//     rig (continuous part) is discretised exactly: matrix exponentials over the held intervals,
//     a fractional delay split into its two held pieces. No Pade or other approximation: the
//     discrete closed loop is exact for the linearised rig and the linear (unsaturated) PID.
// This is the same structure as the firmware's discrete loop (PidAxis + AxisTransform).
#include <array>
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "model/control/pid_params.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"

namespace amb::model::analysis {

struct ClosedLoopOptions {
  double spin_hz = 0.0;             ///< rotor speed, Hz
  double sample_rate_hz = 0.0;      ///< loop rate of the sampled controller, Hz; 0: continuous (analog) PID
  double loop_delay_periods = 0.0;  ///< sampled only: sample instant -> demand applied, in periods (0 .. 8)
  int modes_per_plane = -1;         ///< modal basis; -1: the rig's modes_kept, 0: all FE modes
};

/// One closed-loop eigenvalue pair (Im > 0 member). For the sampled loop the eigenvalue is the
/// continuous equivalent s = ln(z) / T of the discrete one.
struct ClosedLoopMode {
  std::complex<double> eigenvalue;  ///< 1/s
  double natural_rad_s = 0.0;       ///< |lambda|, rad/s
  double damping_ratio = 0.0;       ///< -Re(lambda) / |lambda|
  double rotor_share = 0.0;         ///< 0..1: participation of the rotor states (see .cpp)
};

/// ISO 14839-3 evaluation zones for the peak of the sensitivity function:
/// A < 3 (9.5 dB) newly commissioned; B < 4 (12 dB) unrestricted long-term operation;
/// C < 5 (14 dB) restricted operation; D >= 5 damage may occur.
enum class IsoZone { A, B, C, D };
IsoZone iso14839_zone(double sensitivity_peak);
const char* to_string(IsoZone z);

struct SensitivityPeak {
  double peak = 0.0;           ///< max |S(j w)|
  double peak_db = 0.0;        ///< 20 log10(peak)
  double frequency_hz = 0.0;   ///< where
  IsoZone zone = IsoZone::D;
};

/// Responses of the closed loop to a current injected at one axis' demand (as sensitivity()).
struct InjectionResponse {
  std::complex<double> demand;                       ///< demand sent to the amplifier per injected A: S, 1
  std::array<std::complex<double>, 4> sensor_m_per_a{};  ///< sensor readings [A1, A2, B1, B2] per injected A, m/A
};

class ClosedLoopModel {
 public:
  /// Throws std::invalid_argument if the rig cannot be built (see rotor_model.hpp) or an
  /// option is out of range (sample rate < 0, delay outside 0 .. 8 periods).
  ClosedLoopModel(const PlantParams& rig, const PidParams& pid, const ClosedLoopOptions& o = {});
  /// The same on a rig model built once by the caller (model/rig); `rig` carries the AMB,
  /// sensor and amplifier parameters and must describe the rig model's rotor and planes.
  ClosedLoopModel(const RigModel& rig_model, const PlantParams& rig, const PidParams& pid, const ClosedLoopOptions& o = {});

  /// Closed-loop state matrix: dx/dt = A x (continuous) or x[k+1] = A x[k] (sampled).
  const Eigen::MatrixXd& a() const { return a_; }
  int state_count() const { return static_cast<int>(a_.rows()); }
  bool sampled() const { return period_s_ > 0.0; }

  /// True if every eigenvalue has a negative real part (sampled: lies inside the unit circle).
  bool stable() const;
  /// Largest real part of the (continuous-equivalent) eigenvalues, 1/s.
  double spectral_abscissa() const;
  /// Oscillatory eigenvalues (Im > 0), ascending natural frequency.
  std::vector<ClosedLoopMode> modes() const;
  /// Rotor-dominated modes (rotor_share >= min_share), with x/y duplicates (frequencies
  /// within `merge_rel` of each other) merged, ascending.
  std::vector<ClosedLoopMode> rotor_modes(double min_share = 0.5, double merge_rel = 0.01) const;

  /// Sensitivity S = 1 / (1 + L) at actuator axis `axis` (0..3, [A1, A2, B1, B2]): the loop
  /// broken at that axis' current demand, all other loops closed (ISO 14839-3). Sampled: the
  /// injection is added to the digital demand, S evaluated at z = exp(j 2 pi f T).
  std::complex<double> sensitivity(int axis, double frequency_hz) const;
  /// The demand and the four sensor readings per unit injection at axis `axis` (0..3), f_hz.
  InjectionResponse injection_response(int axis, double f_hz) const;
  /// Peak of |S| over [f_min, f_max] Hz: log grid then golden-section refinement.
  SensitivityPeak sensitivity_peak(int axis, double f_min_hz, double f_max_hz, int grid_points = 800) const;

 private:
  Eigen::MatrixXd a_;
  std::vector<Eigen::VectorXd> b_inj_;     // per axis: state derivative (or next state) per unit injected current
  std::vector<Eigen::RowVectorXd> c_cmd_;
  Eigen::MatrixXd c_sensor_;               // 4 x states: sensor readings  // per axis: current demand before injection
  std::vector<int> group_;                 // per state: participation group (see modes())
  int groups_ = 0, rotor_groups_ = 0;      // groups in all; the first rotor_groups_ are the rotor's
  int modes_ = 0;
  double period_s_ = 0.0;                  // 0: continuous
};

}  // namespace amb::model::analysis
