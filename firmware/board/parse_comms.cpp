#include "firmware/board/parse_comms.hpp"

#include <set>

namespace amb::board {

namespace {

void parse_can(TableReader r, comms::CanParams& c) {
  c.interface = r.string_or("interface", c.interface);
  if (c.interface.empty() || c.interface.size() > 15)
    r.fail("interface", "must be a network interface name of 1..15 characters");
  c.fd = r.boolean_or("fd", c.fd);
  c.board_node_id = static_cast<uint8_t>(r.integer_or("board_node_id", c.board_node_id, 1, 127));
  c.sensor_node_id = static_cast<uint8_t>(r.integer_or("sensor_node_id", c.sensor_node_id, 1, 127));
  c.amplifier_node_id = static_cast<uint8_t>(r.integer_or("amplifier_node_id", c.amplifier_node_id, 1, 127));
  const std::set<int> ids{c.board_node_id, c.sensor_node_id, c.amplifier_node_id};
  if (ids.size() != 3) r.fail("board_node_id", "the board, sensor and amplifier node ids must differ");
  c.heartbeat_period_ms = static_cast<uint32_t>(r.integer_or("heartbeat_period_ms", c.heartbeat_period_ms, 10, 10000));
  c.node_timeout_ms = static_cast<uint32_t>(r.integer_or("node_timeout_ms", c.node_timeout_ms, 1, 60000));
  c.bus_off_restart_ms = static_cast<uint32_t>(r.integer_or("bus_off_restart_ms", c.bus_off_restart_ms, 1, 60000));
  r.finish();
}

void parse_gpio(TableReader r, comms::GpioParams& g) {
  g.enabled = r.boolean_or("enabled", g.enabled);
  g.chip = r.string_or("chip", g.chip);
  if (g.chip.empty()) r.fail("chip", "must name a GPIO chip (e.g. \"gpiochip0\")");
  g.amplifier_enable_line = static_cast<int>(r.integer_or("amplifier_enable_line", g.amplifier_enable_line, 0, 1023));
  g.amplifier_fault_line = static_cast<int>(r.integer_or("amplifier_fault_line", g.amplifier_fault_line, 0, 1023));
  g.landing_request_line = static_cast<int>(r.integer_or("landing_request_line", g.landing_request_line, 0, 1023));
  g.watchdog_line = static_cast<int>(r.integer_or("watchdog_line", g.watchdog_line, 0, 1023));
  g.status_line = static_cast<int>(r.integer_or("status_line", g.status_line, 0, 1023));
  const std::set<int> lines{g.amplifier_enable_line, g.amplifier_fault_line, g.landing_request_line,
                            g.watchdog_line, g.status_line};
  if (lines.size() != 5) r.fail("amplifier_enable_line", "the five line offsets must differ");
  r.finish();
}

void parse_modbus(TableReader r, comms::ModbusParams& m) {
  m.bind_address = r.string_or("bind_address", m.bind_address);
  // Dotted IPv4 only (libmodbus TCP binds IPv4).
  int dots = 0;
  bool digits_only = !m.bind_address.empty();
  for (char ch : m.bind_address) {
    if (ch == '.') ++dots;
    else if (ch < '0' || ch > '9') digits_only = false;
  }
  if (!digits_only || dots != 3) r.fail("bind_address", "must be a dotted IPv4 address such as \"127.0.0.1\" (loopback) or \"0.0.0.0\" (every interface)");
  m.port = static_cast<uint16_t>(r.integer_or("port", m.port, 1, 65535));
  m.unit_id = static_cast<uint8_t>(r.integer_or("unit_id", m.unit_id, 1, 247));
  m.max_clients = static_cast<int>(r.integer_or("max_clients", m.max_clients, 1, 16));
  // The arm key is a guard against accidental command writes (a stray client, a wrong
  // register), not a password: Modbus TCP carries it in clear text.
  m.arm_key = static_cast<uint32_t>(r.integer_or("arm_key", m.arm_key, 1, 0xFFFFFFFFll));
  m.arm_window_ms = static_cast<uint32_t>(r.integer_or("arm_window_ms", m.arm_window_ms, 100, 60000));
  r.finish();
}

}  // namespace

void parse_comms(TableReader r, comms::CommsParams& c) {
  c.present = true;
  c.data_dir = r.string_or("data_dir", c.data_dir);
  if (c.data_dir.empty() || c.data_dir[0] != '/') r.fail("data_dir", "must be an absolute path");
  if (r.has("can")) parse_can(r.table("can"), c.can);
  if (r.has("gpio")) parse_gpio(r.table("gpio"), c.gpio);
  if (r.has("modbus")) parse_modbus(r.table("modbus"), c.modbus);
  r.finish();
}

}  // namespace amb::board
