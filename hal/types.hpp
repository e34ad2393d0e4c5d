#pragma once
// Fixed-size messages that cross the HAL. Units are in the field names.
#include <array>
#include <cstdint>

namespace amb::hal {

/// Control axes handled by one board: two radial AMBs x two actuator axes each.
/// Channel order everywhere: [AMB A axis 1, AMB A axis 2, AMB B axis 1, AMB B axis 2].
inline constexpr int k_axes = 4;
/// Displacement sensor channels (one per control axis, non-collocated planes).
inline constexpr int k_sensors = 4;

/// One sample of the analog front end, taken at the start of a loop period.
struct AnalogInputs {
  int64_t t_ns = 0;                                   ///< HAL clock time of the sample, ns
  std::array<double, k_sensors> displacement_m{};     ///< sensor readings along each sensor axis, m
  std::array<double, k_axes> coil_current_a{};        ///< measured control current per actuator axis, A
  double tach_speed_hz = -1.0;                        ///< tachometer speed if the rig has one, Hz; <0: none
  uint32_t fault_bits = 0;                            ///< per-channel front-end faults (bit i: channel i invalid)
};

/// Demands written to the amplifiers at the end of a loop period.
struct AnalogOutputs {
  std::array<double, k_axes> current_demand_a{};      ///< control-current demand per actuator axis, A
  bool amplifiers_enabled = false;                    ///< false: amplifiers off (rotor on touchdown bearings)
  double spin_speed_command_hz = 0.0;                 ///< drive speed set-point passed to the motor drive, Hz
};

/// Discrete (digital) lines in.
struct DiscreteInputs {
  bool amplifier_fault = false;   ///< amplifier reports a fault
  bool landing_request = false;   ///< operator/PLC requests a controlled landing
  bool external_trigger = false;  ///< external capture trigger
};

/// Discrete lines out.
struct DiscreteOutputs {
  bool amplifier_enable = false;  ///< enables the power stages
  bool watchdog = false;          ///< toggled every loop period while the loop is healthy
  bool status_ok = false;         ///< lit while no fault is latched
};

/// A CAN or CAN FD frame (payload up to 64 bytes).
struct CanFrame {
  uint32_t id = 0;              ///< 11- or 29-bit identifier
  bool extended = false;        ///< 29-bit identifier
  bool fd = false;              ///< CAN FD frame
  bool error = false;           ///< error frame reported by the controller
  uint8_t len = 0;              ///< payload bytes, 0..8 (classic) or 0..64 (FD)
  std::array<uint8_t, 64> data{};
};

/// Counters a CAN backend keeps; never reset except at configure.
struct CanStats {
  uint64_t tx_frames = 0, rx_frames = 0;
  uint64_t tx_dropped = 0;      ///< send would block or failed
  uint64_t rx_dropped = 0;      ///< kernel or ring overflow
  uint64_t error_frames = 0;
  uint64_t bus_off_events = 0;
  uint64_t malformed = 0;       ///< frames refused by the protocol layer
};

}  // namespace amb::hal
