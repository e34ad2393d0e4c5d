#pragma once
// Frequency-domain model of a levitated rig in closed loop, with the model elements of
// effect_set.hpp switched in or out: the host's "model" in the residual loop. Allocates at
// construction (host side only).
//
// Structure at angular frequency w (spin Omega fixed):
//   mechanics  D(w) q = Bi i + f,   D = K + j w (C + Omega G) - w^2 M - sum_j ks n_j n_j^T
//              q = [rotor modal x (m); rotor modal y (m); pedestal x, y (if any)]
//              n_j: generalised direction of actuator axis j (rotor at the AMB minus stator)
//              Bi = [ki_eff n_j]
//   sensors    y = Fs(w) S q + e                  (e: noise, runout, m; Fs first-order roll-off;
//                                                  sensor_gain: each reading's S row scaled by its gain)
//   controller d = Kc(w) y                        (the firmware's discrete PID + notches at
//                                                  z = e^{j w T}, sensor->xy->actuator axes, / ki)
//   amplifier  i = A(w) d + i_inj                 (zero-order hold, board bandwidth, extra lag)
// so (I - A Kc T) i = A Kc e + i_inj with T = Fs S D^-1 Bi. Outputs are ordered
// [sensor readings A1, A2, B1, B2 (m); coil currents per actuator axis (A)] as the HAL.
// Forced inputs f (unbalance) enter through e_f = Fs S D^-1 f.
//
// Frames and angles as in rotor_amb_plant.hpp. A forward-rotating force or runout of
// complex amplitude F has (x, y) components Re(F e^{j w t} (1, -j)).
#include <array>
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "model/control/pid_params.hpp"
#include "model/effects/effect_set.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rig/rig_model.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::effects {

using cd = std::complex<double>;

/// Closed-loop frequency response at one frequency.
struct LoopResponse {
  Eigen::MatrixXcd noise;        ///< 8 x 4: outputs per unit additive signal at each sensor (m/m, A/m)
  Eigen::MatrixXcd injection;    ///< 8 x 4: outputs per unit current added after each amplifier (m/A, A/A)
  Eigen::MatrixXcd accel_injection; ///< P x 4: acceleration (m/s^2) at the requested points per injected A
};

/// The static (DC) operating point of the levitated rig under gravity.
struct StaticPoint {
  std::array<double, 4> sensor_m{};   ///< sensor readings, m (0: the integrators centre them)
  std::array<double, 4> current_a{};  ///< coil control currents, A
  std::array<double, 4> ki_ratio{};   ///< local force per current relative to the board ki, 1
};

/// An acceleration measuring point on the rotor.
struct AccelPoint {
  double axial_m = 0.0;    ///< position from the rotor's left end, m
  double angle_deg = 0.0;  ///< measuring direction from the upward vertical towards +x, deg
};

class EffectLoopModel {
 public:
  /// rate_hz: controller sample rate (Hz); spin_hz: rotor speed (Hz).
  /// Throws std::invalid_argument for an unusable rig (see rotor_model.hpp).
  EffectLoopModel(const PlantParams& rig, const PidParams& pid, double rate_hz, double spin_hz,
                  const EffectSet& effects);
  /// The same on a rig model built once by the caller (shared, read only; model/rig). `rig`
  /// carries what the residual engine varies; its rotor and planes must be the rig model's.
  EffectLoopModel(std::shared_ptr<const RigModel> rig_model, const PlantParams& rig, const PidParams& pid, double rate_hz,
                  double spin_hz, const EffectSet& effects);

  /// Closed-loop responses at `f_hz` (> 0). `points`: accelerations to report for injection.
  LoopResponse at(double f_hz, const std::vector<AccelPoint>& points = {}) const;

  /// Outputs (8) per forward-rotating force of unit complex amplitude (N) at `axial_m`,
  /// at frequency f_hz (e.g. unbalance m e Omega^2 at f = spin).
  Eigen::VectorXcd forward_force(double f_hz, double axial_m) const;
  /// Outputs (8) per unit forward-rotating runout (m) at the sensors of `plane` (0 or 1).
  Eigen::VectorXcd forward_runout(double f_hz, int plane) const;

  /// Static operating point under gravity, levitated (integral action centres the sensors).
  StaticPoint static_levitated() const;
  /// Sensor readings (m) with the rotor at rest on both auxiliary bearings (amplifiers off),
  /// aux-bearing centres offset as the model's aux_bearing_offset says (none: board values).
  std::array<double, 4> rest_sensors_m() const;

  /// Actual coil current per current demand of actuator axis `axis` at f_hz (zero-order hold,
  /// the board's amplifier bandwidth, the extra lag and loop delay when present), 1.
  cd amplifier_response(int axis, double f_hz) const;

  /// Force per measured current of actuator axis j (board ki x force_scale x saturation slope), N/A.
  double ki_eff(int axis) const { return ki_eff_[static_cast<size_t>(axis)]; }

  int modes() const { return m_; }
  const EffectSet& effects() const { return fx_; }

 private:
  Eigen::MatrixXcd dynamic_stiffness(double w) const;
  Eigen::Matrix4cd controller(double w) const;   // demand (A) per sensor reading (m)
  cd amplifier(int axis, double w) const;        // actual current per demand

  PlantParams rig_;
  PidParams pid_;
  double rate_hz_ = 0.0, spin_rad_s_ = 0.0;
  EffectSet fx_;
  std::shared_ptr<const RigModel> model_;  // shared, read only
  const rotor::RotorModel& fe() const { return model_->rotor(); }
  const rotor::ReducedRotor& red() const { return model_->board_reduction().reduced; }
  int m_ = 0, n_ = 0, ped_ = -1;                   // modes per plane, coordinates, pedestal index
  Eigen::MatrixXd k_, c_, g_, mass_;               // n x n
  std::array<Eigen::VectorXd, 4> n_amb_;           // generalised actuator directions
  std::array<Eigen::VectorXd, 4> s_row_;           // generalised sensor rows
  Eigen::VectorXd gravity_;                        // generalised gravity force, N
  std::array<double, 4> ki_eff_{};                 // force per measured current, N/A
  StaticPoint static_{};
};

}  // namespace amb::model::effects
