#pragma once
// The measured-event exchange format (shared/formats/measured-event.md,
// `amb-measured-event/1`: NAME.json sidecar + NAME.csv) as a DropMeasurement. Written here
// because no shared event loader exists yet; when host-tools/core/events/load_event.hpp
// lands, an adapter from its LoadedEvent replaces read_measured_event() in cmd_fit.
//
// Reading: displacement channels are matched to the rig's four sensors by axial position
// (within 5 mm) and direction (within 1 deg); units are converted to SI (m, mm, um; speed in
// rpm or Hz); a malformed file is refused with an error naming file, field or row.
// declared_faults: "amb_cutoff_all" (all amplifier channels cut: the drop of seed 000) is
// understood; any other name is refused rather than ignored.
#include <stdexcept>
#include <string>

#include "host-tools/core/fit/drop_measurement.hpp"
#include "model/plant/plant_params.hpp"

namespace amb::host::fit {

/// A refused measured-event file; what() names the file and the problem.
class MeasuredEventError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Read NAME.json (path given, or the .csv next to it) and its CSV against the rig's sensors.
/// The rig named in the sidecar is returned in `rig`; the caller loads the board.
DropMeasurement read_measured_event(const std::string& json_path, const model::PlantParams& rig_for_matching);

/// The rig named in a sidecar (to load the board before read_measured_event).
std::string measured_event_rig(const std::string& json_path);

/// Write a measurement as NAME.json + NAME.csv (`stem` without extension), sensors in m,
/// speed in rpm, sensor geometry from `rig`. Used by generators and tests.
void write_measured_event(const std::string& stem, const DropMeasurement& m, const model::PlantParams& rig,
                          const std::string& notes);

}  // namespace amb::host::fit
