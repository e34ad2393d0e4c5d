#pragma once
// Which board a command uses with an event: the event's own rig by default, or the board the
// user gave with --board, which must be of the same rig unless forced. One function for every
// command that loads an event and a board (fit, wear-id; the residual loop can call it from
// its loading path), so a board of another rig is refused the same way everywhere instead of
// running and landing on a bound.
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/loaded_event.hpp"

namespace amb::host {

/// Refuses a board of another rig than the event's: throws std::invalid_argument naming
/// both rigs and the way out (--force), unless `force`. `event_rig`: the rig the event names
/// (empty: no check); `board_rig`: the board's rig name; `board_given`: what the user gave.
void check_board_matches_event_rig(const std::string& event_rig, const std::string& board_rig,
                                   const std::string& board_given, bool force);

/// The rig `ev` was recorded on, as a rig name (the sidecar may name a board or a board file;
/// resolved where possible, else the name as written).
std::string event_rig_name(const LoadedEvent& ev);

/// The board for `ev`: `board_given` empty -> the board the event's rig names (resolve_rig,
/// relative to the event's folder); else load_board(board_given), checked against the
/// event's rig with check_board_matches_event_rig. Throws EventLoadError / BoardError /
/// std::invalid_argument (all bad input).
board::BoardConfig board_for_loaded_event(const LoadedEvent& ev, const std::string& board_given, bool force);

}  // namespace amb::host
