#include "host-tools/core/events/event_board_choice.hpp"

#include <filesystem>
#include <stdexcept>

#include "host-tools/core/events/measured_event.hpp"

namespace amb::host {

void check_board_matches_event_rig(const std::string& event_rig, const std::string& board_rig,
                                   const std::string& board_given, bool force) {
  if (force || event_rig.empty() || board_rig.empty() || event_rig == board_rig) return;
  throw std::invalid_argument("--board '" + board_given + "' is a board of rig '" + board_rig +
                              "', but the event was recorded on rig '" + event_rig +
                              "'; give the event's board, or --force to use this one anyway");
}

std::string event_rig_name(const LoadedEvent& ev) {
  try {
    return resolve_rig(ev.rig, std::filesystem::path(ev.source).parent_path().string(), ev.source).plant.rig_name;
  } catch (const std::exception&) {
    return ev.rig;  // not resolvable here: compare the name as written
  }
}

board::BoardConfig board_for_loaded_event(const LoadedEvent& ev, const std::string& board_given, bool force) {
  const std::string dir = std::filesystem::path(ev.source).parent_path().string();
  if (board_given.empty()) return resolve_rig(ev.rig, dir, ev.source);
  board::BoardConfig b = board::load_board(board_given);
  check_board_matches_event_rig(event_rig_name(ev), b.plant.rig_name, board_given, force);
  return b;
}

}  // namespace amb::host
