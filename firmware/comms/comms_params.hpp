#pragma once
// The board's I/O wiring for the linux backend: the CAN field bus to the sensor and amplifier
// nodes, the discrete lines on a GPIO chip, and the supervisory (Modbus TCP) link. Read from
// the optional `[comms]` table of a board file (firmware/board/parse_comms.cpp); a board
// without it keeps `present == false` and the defaults below.
#include <cstdint>
#include <string>

namespace amb::comms {

/// Field bus (SocketCAN). Node ids are 7-bit (CANopen style: id = function << 7 | node).
struct CanParams {
  std::string interface = "can0";     ///< SocketCAN network interface, e.g. "can0", "vcan0"
  bool fd = false;                    ///< use CAN FD frames (one 48-byte sample frame per period)
  uint8_t board_node_id = 1;          ///< this board's node id, 1..127
  uint8_t sensor_node_id = 2;         ///< displacement-sensor node id, 1..127
  uint8_t amplifier_node_id = 3;      ///< amplifier node id (demands in, measured currents out), 1..127
  uint32_t heartbeat_period_ms = 100; ///< period of this board's heartbeat frame, ms
  uint32_t node_timeout_ms = 50;      ///< no frame from a node for this long while levitated: safe state, ms
  uint32_t bus_off_restart_ms = 100;  ///< wait after bus-off before the controller is restarted, ms
};

/// Discrete lines on one GPIO chip (libgpiod v1.6 character device).
struct GpioParams {
  std::string chip = "gpiochip0";     ///< chip name or path (/dev/gpiochipN)
  int amplifier_enable_line = 0;      ///< output: enables the power stages
  int amplifier_fault_line = 1;       ///< input: amplifier fault (active high)
  int landing_request_line = 2;       ///< input: landing request from the operator/PLC (active high)
  int watchdog_line = 3;              ///< output: toggled every period while the loop is healthy
  int status_line = 4;                ///< output: lit while no fault is latched
  bool enabled = true;                ///< false: no GPIO chip (discrete lines read as idle)
};

/// Supervisory link (Modbus TCP server) and its write access (docs/register-map.md).
struct ModbusParams {
  std::string bind_address = "127.0.0.1"; ///< IPv4 address the server listens on (default: loopback only)
  uint16_t port = 502;                  ///< TCP port, 1..65535
  uint8_t unit_id = 1;                  ///< Modbus unit identifier answered (also 0 and 255), 1..247
  int max_clients = 4;                  ///< simultaneous TCP connections served, 1..16
  /// Key of the arm sequence (register 0x0F00) that every command write needs, 1..2^32-1.
  /// 0 (absent from the board file): the board takes no commands over Modbus at all.
  uint32_t arm_key = 0;
  uint32_t arm_window_ms = 5000;        ///< an arm expires this long after it was written, ms (100..60000)
};

struct CommsParams {
  bool present = false;               ///< the board file has a [comms] table
  std::string data_dir = "/var/lib/amb"; ///< persistent storage root (events/, wear/); env AMB_DATA_DIR overrides
  CanParams can;
  GpioParams gpio;
  ModbusParams modbus;
};

}  // namespace amb::comms
