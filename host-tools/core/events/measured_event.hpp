#pragma once
// The measured-event exchange format `amb-measured-event/1` (../shared/formats/
// measured-event.md): NAME.json sidecar + NAME.csv. Reading validates everything and
// converts to SI; writing produces files that reading accepts.
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/loaded_event.hpp"

namespace amb::host {

inline constexpr const char* k_measured_event_format = "amb-measured-event/1";

/// The two file paths of a measured event given the .json, the .csv or the stem.
struct MeasuredEventPaths {
  std::string json, csv;
};
MeasuredEventPaths measured_event_paths(const std::string& path);

/// Find the board a sidecar's "rig" names: an embedded board whose board or rig name it is,
/// or a board file path (absolute, or relative to `relative_to_dir`). Throws EventLoadError.
board::BoardConfig resolve_rig(const std::string& rig, const std::string& relative_to_dir, const std::string& file);

/// Read a measured event. Throws EventLoadError naming the file and the row or field.
/// Channels are matched to the rig by axial position and angle within the board's
/// capture.match_*_tolerance; unmatched channels are kept with rig_index -1 and a warning.
LoadedEvent read_measured_event(const std::string& path);

/// Columns to write: each with its quantity, unit (SI: m, A, Hz, s, m/s^2, V) and position.
struct MeasuredColumn {
  std::string column, quantity, unit;
  bool positioned = false;          ///< axial_m / angle_deg are written
  double axial_m = 0.0, angle_deg = 0.0;
  const std::vector<double>* values = nullptr;
  bool in_sidecar = true;           ///< false: an extra CSV column, ignored by importers
};

struct MeasuredEventOut {
  std::string rig;
  double sample_rate_hz = 0.0;
  size_t trigger_index = 0;
  std::optional<double> speed_rpm;
  std::vector<MeasuredColumn> columns;
  std::vector<std::string> declared_faults;
  std::string notes;
};

/// Write STEM.csv and STEM.json (each via a temporary file renamed into place). Throws
/// std::runtime_error on I/O failure.
void write_measured_event(const std::string& stem, const MeasuredEventOut& e);

/// A LoadedEvent in the exchange format: time, displacements, currents, speed (plus the
/// board's demands and clock as extra CSV columns).
void export_measured_event(const LoadedEvent& e, const std::string& stem);

}  // namespace amb::host
