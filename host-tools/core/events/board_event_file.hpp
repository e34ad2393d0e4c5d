#pragma once
// Board event files (AMBE v1 and v2) on the host: read with full checks, convert to LoadedEvent.
#include <string>

#include "firmware/events/event_record.hpp"
#include "host-tools/core/events/loaded_event.hpp"

namespace amb::host {

/// True if the file starts with the AMBE magic.
bool is_board_event_file(const std::string& path);

/// Read and decode; throws EventLoadError "PATH: truncated: ..." / "bad checksum" / ...
fw::EventRecord read_board_event(const std::string& path);

/// The record as a LoadedEvent (SI channels; sensors and actuators from its own calibration).
LoadedEvent to_loaded_event(const fw::EventRecord& r, const std::string& source);

}  // namespace amb::host
