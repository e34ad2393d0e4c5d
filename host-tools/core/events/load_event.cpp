#include "host-tools/core/events/load_event.hpp"

#include <filesystem>

#include "host-tools/core/events/board_event_file.hpp"
#include "host-tools/core/events/measured_event.hpp"

namespace amb::host {

LoadedEvent load_event(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(path, ec) && is_board_event_file(path)) return to_loaded_event(read_board_event(path), path);
  const fs::path p(path);
  if (p.extension() == ".json" || p.extension() == ".csv" || fs::is_regular_file(measured_event_paths(path).json, ec))
    return read_measured_event(path);
  if (!fs::exists(path, ec)) throw EventLoadError(path + ": no such file (nor " + measured_event_paths(path).json + ")");
  throw EventLoadError(path + ": neither a board event file (AMBE) nor a measured event (.json sidecar + .csv)");
}

}  // namespace amb::host
