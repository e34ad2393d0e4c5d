#pragma once
// The plant seen by the HAL sim backend: anything that can be stepped with amplifier demands
// and sampled like the rig's sensors. The penalty-contact rotor-AMB plant implements it now;
// the non-smooth (Moreau-Jean) drop model implements it later and can replace it.
#include <array>
#include <cstdint>

#include "model/plant/plant_params.hpp"

namespace amb::model {

/// What the amplifiers and the drive are told for the next interval.
struct PlantInputs {
  std::array<double, 4> current_demand_a{};  ///< control-current demand per actuator axis, A
  bool amplifiers_enabled = false;           ///< false: coils carry no current (bias included)
  double spin_speed_command_hz = 0.0;        ///< drive set-point, Hz
};

/// What the rig's sensors see now.
struct PlantOutputs {
  double t_s = 0.0;                              ///< plant time, s
  std::array<double, 4> displacement_m{};        ///< sensor readings along each sensor axis (noise incl.), m
  std::array<double, 4> coil_current_a{};        ///< actual control current per actuator axis, A
  double spin_speed_hz = 0.0;                    ///< true rotor speed, Hz
  double spin_angle_rad = 0.0;                   ///< rotor angle, rad
};

/// Ground-truth state for tests and the host (never available to the firmware).
struct PlantTruth {
  std::array<double, 2> aux_x_m{}, aux_y_m{};    ///< rotor centre at each aux-bearing plane, m
  std::array<double, 2> contact_force_n{};       ///< normal contact force at each aux bearing, N
  std::array<double, 2> friction_force_n{};      ///< tangential friction force, N
  std::array<double, 2> ring_speed_rad_s{};      ///< aux inner-ring speed, rad/s
  std::array<double, 2> amb_x_m{}, amb_y_m{};    ///< rotor centre at each AMB plane, m
  std::array<double, 4> amb_force_n{};           ///< force per actuator axis, N
  double kinetic_energy_j = 0.0;
  double potential_energy_j = 0.0;               ///< elastic + gravity
  double friction_dissipated_j = 0.0;            ///< cumulative friction work at the contacts, J
};

class Plant {
 public:
  virtual ~Plant() = default;
  /// Put the rotor at rest on the touchdown bearings (or levitated at the centre if
  /// `levitated`), spin speed `spin_hz`, time 0, faults cleared.
  virtual void reset(bool levitated, double spin_hz) = 0;
  /// Advance by `dt_s` holding `in` constant (internally sub-stepped). No allocation.
  virtual void step(double dt_s, const PlantInputs& in) = 0;
  /// Sensor view now.
  virtual PlantOutputs outputs() const = 0;
  /// Ground truth now.
  virtual PlantTruth truth() const = 0;
  /// Fault injection (SIL only).
  virtual void set_faults(const PlantFaults& faults) = 0;
};

}  // namespace amb::model
