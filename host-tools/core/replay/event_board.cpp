#include "host-tools/core/replay/event_board.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "firmware/events/event_codec.hpp"

namespace amb::host::replay {

namespace {
/// The event stores doubles as written from the board, so equal means equal.
void require_same(const char* what, double event_value, double board_value, const board::BoardConfig& b,
                  const fw::EventRecord& e) {
  if (event_value == board_value || (std::isnan(event_value) && std::isnan(board_value))) return;
  throw std::runtime_error(std::string("board '") + b.name + "' (" + b.source + ") does not match the event: " +
                           what + " is " + std::to_string(event_value) + " in the event but " +
                           std::to_string(board_value) + " in the board. The event was recorded with '" +
                           e.meta.board_source + "'; pass that board file with --board FILE.");
}
}  // namespace

board::BoardConfig board_for_event(const fw::EventRecord& e, const std::string& board_override) {
  const std::string name = board_override.empty() ? e.meta.board_name : board_override;
  if (name.empty()) throw std::runtime_error("the event names no board; pass one with --board NAME|FILE");
  board::BoardConfig b;
  try {
    b = board::load_board(name);
  } catch (const std::exception& ex) {
    throw std::runtime_error("cannot load board '" + name + "' named by the event: " + ex.what() +
                             ". Pass the board the event was recorded with: --board NAME|FILE");
  }
  require_same("rate_hz", e.meta.rate_hz, b.rate_hz, b, e);
  require_same("controller.kp_n_per_m", e.meta.kp_n_per_m, b.controller.kp_n_per_m, b, e);
  require_same("controller.ki_n_per_m_s", e.meta.ki_n_per_m_s, b.controller.ki_n_per_m_s, b, e);
  require_same("controller.kd_n_s_per_m", e.meta.kd_n_s_per_m, b.controller.kd_n_s_per_m, b, e);
  require_same("controller.derivative_filter_hz", e.meta.derivative_filter_hz, b.controller.derivative_filter_hz, b, e);
  require_same("controller.integrator_limit_n", e.meta.integrator_limit_n, b.controller.integrator_limit_n, b, e);
  require_same("controller.current_limit_a", e.meta.current_limit_a, b.controller.current_limit_a, b, e);
  for (size_t i = 0; i < 4; ++i) {
    const std::string k = "[" + std::to_string(i) + "]";
    require_same(("sensor" + k + ".angle_deg").c_str(), e.meta.sensors[i].angle_deg, b.plant.sensor[i].angle_deg, b, e);
    require_same(("sensor" + k + ".axial_m").c_str(), e.meta.sensors[i].axial_m, b.plant.sensor[i].axial_m, b, e);
    const auto& amb = b.plant.amb[i / 2];
    require_same(("actuator" + k + ".angle_deg").c_str(), e.meta.actuators[i].angle_deg, amb.actuator_angle_deg[i % 2], b, e);
    require_same(("actuator" + k + ".ki_n_per_a").c_str(), e.meta.actuators[i].ki_n_per_a, amb.ki_n_per_a, b, e);
  }
  // The replayed capture is configured like the recording one.
  if (e.meta.pre_trigger_s >= 0.0 && e.meta.post_trigger_s > 0.0) {
    b.capture.pre_trigger_s = e.meta.pre_trigger_s;
    b.capture.post_trigger_s = e.meta.post_trigger_s;
  }
  return b;
}

fw::EventRecord read_event_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open event file '" + path + "' (check the path; `amb-host fetch` downloads events from a board)");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fw::EventRecord r;
  std::string err;
  if (!fw::decode_event(bytes, r, err))
    throw std::runtime_error("'" + path + "' is not a usable AMBE event file: " + err +
                             " (a measured-event export from a DAQ is read by `amb-host import`)");
  return r;
}

}  // namespace amb::host::replay
