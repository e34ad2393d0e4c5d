#pragma once
// The common loader: a board event file (AMBE, any extension) or a measured event
// (amb-measured-event/1: NAME.json + NAME.csv; pass either file or the stem).
#include <string>

#include "host-tools/core/events/loaded_event.hpp"

namespace amb::host {

/// Load and validate an event. Throws EventLoadError naming the file, row or field; nothing
/// is returned half-imported.
LoadedEvent load_event(const std::string& path);

}  // namespace amb::host
