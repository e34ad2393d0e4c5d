#include "host-tools/core/fit/drop_measurement.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "host-tools/core/events/measured_event.hpp"
#include "model/drop/drop_simulation.hpp"

namespace amb::host::fit {

DropMeasurement drop_measurement_from_trace(const model::drop::DropTrace& trace, const model::drop::DropScenario& scenario,
                                            std::string source, std::string rig) {
  DropMeasurement m;
  m.source = std::move(source);
  m.rig = std::move(rig);
  m.sample_rate_hz = scenario.sample_rate_hz;
  m.trigger_index = trace.trigger_index;
  m.speed_at_trigger_hz = scenario.speed_hz;
  m.sensor_m.reserve(trace.samples.size());
  m.speed_rad_s.reserve(trace.samples.size());
  for (const model::drop::DropSample& s : trace.samples) {
    m.sensor_m.push_back(s.sensor_m);
    m.speed_rad_s.push_back(s.spin_rad_s);
  }
  return m;
}

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

DropMeasurement drop_measurement_from_event(const LoadedEvent& e) {
  DropMeasurement m;
  m.source = e.source;
  m.rig = e.rig;
  m.sample_rate_hz = e.sample_rate_hz;
  m.trigger_index = static_cast<int>(e.trigger_index);
  for (const std::string& f : e.declared_faults)
    if (f != "amb_cutoff_all")
      throw EventLoadError(e.source + ": declared fault '" + f + "' is not understood by the fit (known: amb_cutoff_all)");
  m.amplifiers_off = true;  // amb_cutoff_all, or nothing declared: the drop of an AMB switch-off
  std::array<const std::vector<double>*, 4> ch{};
  for (const auto& c : e.displacement)
    if (c.rig_index >= 0 && c.rig_index < 4 && ch[static_cast<size_t>(c.rig_index)] == nullptr) ch[static_cast<size_t>(c.rig_index)] = &c.values;
  for (size_t s = 0; s < 4; ++s)
    if (ch[s] == nullptr) throw EventLoadError(e.source + ": no displacement channel matches sensor " + std::to_string(s) + " of the rig");
  m.sensor_m.resize(e.samples());
  for (size_t i = 0; i < e.samples(); ++i)
    for (size_t s = 0; s < 4; ++s) m.sensor_m[i][s] = (*ch[s])[i];
  for (double f : e.speed_hz) m.speed_rad_s.push_back(2.0 * M_PI * f);
  if (e.speed_at_trigger_hz) m.speed_at_trigger_hz = *e.speed_at_trigger_hz;
  if (!(m.speed_at_trigger_hz > 0.0) && e.trigger_index < e.speed_hz.size()) m.speed_at_trigger_hz = e.speed_hz[e.trigger_index];
  if (const std::string err = m.check(); !err.empty()) throw EventLoadError(e.source + ": " + err);
  return m;
}

void write_drop_measurement(const std::string& stem, const DropMeasurement& m, const model::PlantParams& rig,
                            const std::string& notes) {
  MeasuredEventOut out;
  out.rig = m.rig;
  out.sample_rate_hz = m.sample_rate_hz;
  out.trigger_index = static_cast<size_t>(std::max(m.trigger_index, 0));
  out.speed_rpm = m.speed_at_trigger_hz * 60.0;
  out.declared_faults = m.amplifiers_off ? std::vector<std::string>{"amb_cutoff_all"} : std::vector<std::string>{};
  out.notes = notes;
  const size_t n = m.sensor_m.size();
  std::vector<double> t(n), rpm;
  std::array<std::vector<double>, 4> x;
  for (size_t i = 0; i < n; ++i) {
    t[i] = (static_cast<double>(i) - m.trigger_index) / m.sample_rate_hz;
    for (size_t s = 0; s < 4; ++s) x[s].push_back(m.sensor_m[i][s] * 1e6);
  }
  for (double w : m.speed_rad_s) rpm.push_back(w * 60.0 / (2.0 * M_PI));
  out.columns.push_back({"t_s", "time", "s", false, 0.0, 0.0, &t, true});
  const char* names[4] = {"a1", "a2", "b1", "b2"};
  for (size_t s = 0; s < 4; ++s)
    out.columns.push_back({names[s], "displacement", "um", true, rig.sensor[s].axial_m, rig.sensor[s].angle_deg, &x[s], true});
  if (!rpm.empty()) out.columns.push_back({"n", "speed", "rpm", false, 0.0, 0.0, &rpm, true});
  write_measured_event(stem, out);
}

}  // namespace amb::host::fit
