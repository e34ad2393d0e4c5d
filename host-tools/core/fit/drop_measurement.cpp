#include "host-tools/core/fit/drop_measurement.hpp"

#include <cmath>

namespace amb::host::fit {

std::string DropMeasurement::check() const {
  if (!(sample_rate_hz > 0.0)) return "sample_rate_hz must be > 0";
  if (sensor_m.size() < 2) return "no displacement samples";
  if (trigger_index < 0 || static_cast<size_t>(trigger_index) >= sensor_m.size() - 1)
    return "trigger_index " + std::to_string(trigger_index) + " is outside the " + std::to_string(sensor_m.size()) + " samples";
  if (!speed_rad_s.empty() && speed_rad_s.size() != sensor_m.size()) return "speed channel length differs from the displacements";
  if (!(speed_at_trigger_hz > 0.0)) return "rotor speed at the trigger is unknown (give speed_rpm or a speed channel)";
  for (size_t i = 0; i < sensor_m.size(); ++i)
    for (double v : sensor_m[i])
      if (!std::isfinite(v)) return "displacement sample " + std::to_string(i) + " is not finite";
  return {};
}

}  // namespace amb::host::fit
