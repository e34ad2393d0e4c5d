#pragma once
// The report of a measured event (amb-measured-event/1: a rig's recording, or a drop from a
// simulator outside this project): what the file holds, as add_event does for board events.
// A measured event has no firmware state (nothing to replay) and no board analysis (no
// quick-look); those sections say so.
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/loaded_event.hpp"
#include "host-tools/core/report/report_data.hpp"

namespace amb::host::report {

/// Facts (format, rig and board, sample rate, window, trigger, speed at the trigger, the
/// declared faults, notes and load warnings), orbits at both planes and the rubbing states
/// (add_orbits; needs the four displacement channels matched to the board's sensors), the
/// recorded speed and the cause chain as far as the file tells it. `board`: the board the
/// event was resolved to (board_for_loaded_event); `source`: file name shown in the report.
void add_loaded_event(ReportData& d, const LoadedEvent& e, const board::BoardConfig& board, const std::string& source);

}  // namespace amb::host::report
