#pragma once
// Linearised closed loop of a rig at a given spin speed (host/analysis side; allocates):
//   rotor (modally reduced, gyroscopic, Rayleigh damping)
//   + AMBs linearised at the centre (F = ks z + ki i per actuator axis, at +-45 deg)
//   + sensors at their own planes and angles with first-order roll-off
//   + per bearing plane: sensors -> (x, y), a continuous PID per direction in the form of
//     seed 002 eq. 19, F = -(KP e + KI \int e + KD s/(1 + s/wf) e), the notches
//     (s^2 + depth*BW s + w0^2) / (s^2 + BW s + w0^2), (Fx, Fy) -> actuator axes, i = f / ki
//   + optional loop delay (first-order Pade, for the sampled controller)
//   + first-order current amplifier per actuator axis.
// This is the same structure as the firmware's discrete loop (PidAxis + AxisTransform).
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "model/control/pid_params.hpp"
#include "model/plant/plant_params.hpp"

namespace amb::model::analysis {

struct ClosedLoopOptions {
  double spin_hz = 0.0;        ///< rotor speed, Hz
  double loop_delay_s = 0.0;   ///< controller delay (e.g. 1.5 / rate_hz for a sampled loop), s; 0: none
  int modes_per_plane = -1;    ///< modal basis; -1: the rig's modes_kept, 0: all FE modes
};

/// One closed-loop eigenvalue pair (Im > 0 member).
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

class ClosedLoopModel {
 public:
  /// Throws std::invalid_argument if the rig cannot be built (see rotor_model.hpp).
  ClosedLoopModel(const PlantParams& rig, const PidParams& pid, const ClosedLoopOptions& o = {});

  const Eigen::MatrixXd& a() const { return a_; }  ///< closed-loop state matrix
  int state_count() const { return static_cast<int>(a_.rows()); }

  /// True if every eigenvalue has a negative real part.
  bool stable() const;
  /// Largest real part of the eigenvalues, 1/s.
  double spectral_abscissa() const;
  /// Oscillatory eigenvalues (Im > 0), ascending natural frequency.
  std::vector<ClosedLoopMode> modes() const;
  /// Rotor-dominated modes (rotor_share >= min_share), with x/y duplicates (frequencies
  /// within `merge_rel` of each other) merged, ascending.
  std::vector<ClosedLoopMode> rotor_modes(double min_share = 0.5, double merge_rel = 0.01) const;

  /// Sensitivity S = 1 / (1 + L) at actuator axis `axis` (0..3, [A1, A2, B1, B2]): the loop
  /// broken at that axis' current demand, all other loops closed (ISO 14839-3).
  std::complex<double> sensitivity(int axis, double frequency_hz) const;
  /// Peak of |S| over [f_min, f_max] Hz: log grid then golden-section refinement.
  SensitivityPeak sensitivity_peak(int axis, double f_min_hz, double f_max_hz, int grid_points = 800) const;

 private:
  Eigen::MatrixXd a_;
  std::vector<Eigen::VectorXd> b_inj_;     // per axis: state derivative per unit injected current
  std::vector<Eigen::RowVectorXd> c_cmd_;  // per axis: current demand before injection
  int modes_ = 0;
};

}  // namespace amb::model::analysis
