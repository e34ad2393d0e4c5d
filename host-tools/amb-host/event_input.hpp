#pragma once
// The event file a sub-command reads (amb-host export, import): loaded, or refused with the
// reason on stderr as bad input.
#include <cstdio>
#include <optional>
#include <string>

#include "host-tools/core/events/load_event.hpp"

namespace amb::host {

/// The event at `path` (load_event), or nullopt after printing
/// "amb-host <sub>: error: <why>" on stderr; the caller then exits with 1 (bad input).
inline std::optional<LoadedEvent> load_event_or_report(const std::string& path, const char* sub) {
  try {
    return load_event(path);
  } catch (const EventLoadError& err) {
    std::fprintf(stderr, "amb-host %s: error: %s\n", sub, err.what());
    return std::nullopt;
  }
}

}  // namespace amb::host
