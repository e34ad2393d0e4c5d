#pragma once
// The board an event is replayed with: the one named in the event (or given by the user),
// checked against what the event recorded (loop rate, controller gains and limits, sensor
// and actuator calibration), with the event's capture window lengths. A board that does not
// match is refused with a message that says which value differs and what to do.
#include <string>

#include "firmware/board/board.hpp"
#include "firmware/events/event_record.hpp"

namespace amb::host::replay {

/// `board_override`: a board name or file to use instead of the event's board name (empty:
/// the event's). Throws std::runtime_error when it cannot be loaded or does not match.
board::BoardConfig board_for_event(const fw::EventRecord& event, const std::string& board_override = {});

/// Read and decode an AMBE event file. Throws std::runtime_error naming the file and the problem.
fw::EventRecord read_event_file(const std::string& path);

}  // namespace amb::host::replay
