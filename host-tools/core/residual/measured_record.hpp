#pragma once
// Minimal reader of the measured-event exchange format (formats/measured-event.md,
// `amb-measured-event/1`: NAME.csv + NAME.json) for the residual loop. It reads only those
// two files; values are converted to SI. (The shared importer, host-tools/core/events/,
// did not exist when this was written; switch to it once it does.)
#include <string>
#include <vector>

namespace amb::host::residual {

struct RecordChannel {
  std::string column;     ///< CSV column name
  std::string quantity;   ///< time, displacement, current, speed, acceleration, voltage
  std::string unit;       ///< unit as stored
  double axial_m = 0.0;   ///< axial position, m (displacement/current/acceleration)
  double angle_deg = 0.0; ///< direction from the upward vertical towards +x, deg
  std::vector<double> values;  ///< samples in SI (m, A, Hz for speed, m/s^2, V, s)
};

struct MeasuredRecord {
  std::string path;               ///< the sidecar it came from
  std::string rig;                ///< board name or path
  double sample_rate_hz = 0.0;
  long trigger_index = 0;
  double speed_rpm = -1.0;        ///< -1: not given
  std::vector<RecordChannel> channels;
  std::vector<std::string> declared_faults;
  std::string notes;
  size_t samples() const { return channels.empty() ? 0 : channels.front().values.size(); }
};

/// Read NAME.json (path to the sidecar; NAME.csv next to it). Throws std::runtime_error
/// naming the file and the row or field on malformed input.
MeasuredRecord read_measured_record(const std::string& sidecar_path);

/// Write a record in the same format (used by generators and tests). Values are written in
/// SI with the units "s", "m", "A", "Hz" (speed), "m/s^2", "V".
void write_measured_record(const MeasuredRecord& r, const std::string& sidecar_path);

}  // namespace amb::host::residual
