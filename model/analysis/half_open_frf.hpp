#pragma once
// Frequency response of a rotor on two AMBs in one lateral plane when one actuator's coil
// current is the input ("half-open" loop): what a rig measures with a current-referenced FRF
// (H1 with the measured control current as reference) while the loop is closed. The excited
// bearing contributes its actuator force ki i and its negative stiffness ks on the relative
// rotor-stator displacement (its own controller does not appear: the measured current
// already contains the feedback); the other bearing is closed through its PID. Used by the
// FE model updating of the residual loop (host-tools/core/residual/frf_update.*).
//
// Model: free-free Timoshenko rotor (model/rotor), planar, with
//  * per-element bending-stiffness scales (E scale) and per-disk mass / inertia scales;
//  * lumped accelerometer masses (kg) at their axial positions;
//  * modal damping: damping ratio per free-free flexible mode (rigid-body modes undamped);
//  * per bearing: ks (N/m), ki (N/A), a first-order lag tau of the current amplifier between
//    the controller's current command and the coil current (1 / (1 + s tau): in the closed
//    bearing's loop only, the excited bearing's input is its measured coil current) and the
//    eddy currents in
//    solid (unlaminated) iron of the magnetic circuit: above the iron's field-diffusion corner
//    the skin effect adds a reluctance growing with sqrt(w), so the flux follows mmf and gap
//    changes through G_ec(s) = 1 / (1 + sqrt(s te)) (half order; te: the time constant at
//    which the iron's eddy-current reluctance equals the air gap's). Force = G_ec (ki i + ks x)
//    on both bearings; the closed bearing's PID
//    C(s) = kp + ki_int / s + kd s / (1 + s / w_f) in N/m, a pure loop delay (s), sensor
//    collocated with the actuator, measuring the relative rotor-stator displacement;
//  * optionally a housing (stator) mode per bearing: a mass on a spring to ground with a
//    damping ratio; the bearing force acts between rotor and housing;
//  * attached bodies: point masses with transverse (diametral) inertia (accelerometers, a
//    drive coupling hub on a shaft end), resonators (a mass on a spring and damper attached
//    to the shaft: a flexibly connected part) and lateral supports to ground (spring and
//    viscous damper: a coupling to the drive, a rub-free guide).
// Output per frequency: acceleration (m/s^2) at any axial position per A of input current.
// No I/O. Construction allocates; evaluation allocates small vectors (host-side analysis).
#include <Eigen/Core>
#include <array>
#include <complex>
#include <vector>

#include "model/control/pid_params.hpp"
#include "model/plant/plant_params.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::analysis {

/// Housing (stator) of one bearing as a single-DOF mode to ground. mass_kg <= 0: rigid.
struct HousingMode {
  double mass_kg = 0.0;           ///< modal mass of the housing at the bearing, kg
  double frequency_hz = 0.0;      ///< housing frequency on its spring (bearing force excluded), Hz
  double damping_ratio = 0.0;     ///< viscous damping ratio of the housing mode, 1
};

/// One bearing of the half-open model.
struct HalfOpenBearing {
  double axial_m = 0.0;           ///< actuator (and collocated sensor) plane, m
  double ks_n_per_m = 0.0;        ///< negative stiffness magnitude (force = +ks x), N/m
  double ki_n_per_a = 0.0;        ///< current gain, N/A
  double actuator_lag_s = 0.0;    ///< current-amplifier lag (command -> coil current) in the closed loop, s (0: none)
  double eddy_time_s = 0.0;       ///< eddy-current time constant te of G_ec = 1 / (1 + sqrt(s te)), s (0: none)
  HousingMode housing;            ///< stator compliance (rigid by default)
};

/// Accelerometer (or any attached point mass) on the shaft.
struct AttachedMass {
  double axial_m = 0.0;           ///< position, m
  double mass_kg = 0.0;           ///< mass, kg
  double transverse_inertia_kg_m2 = 0.0;  ///< diametral inertia about the attachment point (needs a node there), kg m^2
};

/// A part attached to the shaft through a spring and a viscous damper (one translational DOF).
struct Resonator {
  double axial_m = 0.0;           ///< attachment point, m
  double mass_kg = 0.0;           ///< moving mass, kg (> 0)
  double frequency_hz = 0.0;      ///< natural frequency on its spring with the shaft held, Hz (> 0)
  double damping_ratio = 0.0;     ///< viscous damping ratio of that resonance, 1
};

/// Lateral spring and viscous damper from the shaft to ground.
struct GroundSupport {
  double axial_m = 0.0;           ///< position, m
  double stiffness_n_per_m = 0.0; ///< N/m (>= 0)
  double damping_n_s_per_m = 0.0; ///< N s/m (>= 0)
};

struct HalfOpenParams {
  RotorParams rotor;                            ///< free-free rotor (nominal)
  std::vector<double> element_stiffness_scale;  ///< per rotor element (empty: all 1), scales E
  std::vector<double> disk_mass_scale;          ///< per disk (empty: all 1)
  std::vector<double> disk_inertia_scale;       ///< per disk, transverse and polar (empty: all 1)
  std::vector<AttachedMass> attached;           ///< accelerometers, coupling hub etc.
  std::vector<Resonator> resonators;            ///< flexibly attached parts
  std::vector<GroundSupport> supports;          ///< lateral supports to ground
  std::vector<double> flexible_damping_ratio;   ///< per free-free flexible mode, low to high, 1
  double default_damping_ratio = 0.005;         ///< flexible modes beyond the list, 1
  int modes_kept = 12;                          ///< free-free modes kept (incl. 2 rigid-body), >= 3
  std::array<HalfOpenBearing, 2> bearing;       ///< [0] left, [1] right
  int excited = 0;                              ///< index of the bearing whose current is the input
  PidParams controller;                         ///< PID of the closed (other) bearing, force form
  double loop_delay_s = 0.0;                    ///< pure delay in the closed bearing's loop, s
};

class HalfOpenFrf {
 public:
  /// Builds the rotor, adds the attached masses and computes the free-free modes.
  /// Throws std::invalid_argument for unusable parameters (sizes, non-positive values).
  explicit HalfOpenFrf(const HalfOpenParams& p);

  /// Eddy-current factor G_ec of a bearing at f_hz (1 without eddy currents).
  static std::complex<double> eddy_factor(const HalfOpenBearing& b, double f_hz);

  /// Modal coordinates (mass-normalised free-free modes) per A of input current at f_hz.
  Eigen::VectorXcd modal_response(double f_hz) const;

  /// Displacement (m per A of input current) seen by the excited bearing's collocated sensor:
  /// the rotor at the bearing plane relative to that bearing's housing (rigid: the ground).
  std::complex<double> sensor_displacement(double f_hz) const;

  /// The closed bearing's controller in force form, PID x loop delay (N/m) at f_hz (the
  /// amplifier lag and the eddy-current factor excluded).
  std::complex<double> controller_force_per_m(double f_hz) const;

  /// Row that maps modal coordinates to the lateral displacement at axial_m (m per unit q).
  Eigen::RowVectorXd shape_row(double axial_m) const;

  /// Acceleration (m/s^2) per A at each position in axial_m.
  std::vector<std::complex<double>> accel_per_current(double f_hz, const std::vector<double>& axial_m) const;

  /// Free-free natural frequencies of the modes kept (Hz), rigid-body ones ~0.
  const std::vector<double>& free_free_hz() const { return free_hz_; }
  double length_m() const { return length_m_; }

 private:
  Eigen::VectorXcd solve(double f_hz) const;  // modal coordinates, then housing DOFs

  HalfOpenParams p_;
  rotor::RotorModel model_;         // assembled rotor incl. attached masses
  Eigen::MatrixXd phi_;             // 2N x n mass-normalised free-free modes
  std::vector<double> free_hz_;
  std::vector<double> omega_, zeta_;
  std::array<Eigen::RowVectorXd, 2> bearing_row_;  // modal rows at the bearing planes
  double length_m_ = 0.0;
};

}  // namespace amb::model::analysis
