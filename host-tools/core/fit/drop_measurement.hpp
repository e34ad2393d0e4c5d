#pragma once
// What the Phase C fit needs from a measured drop, independent of where it came from (a
// board event file, a user's measured-event export, a generator in the tests).
#include <array>
#include <string>
#include <vector>

#include "host-tools/core/events/loaded_event.hpp"
#include "model/plant/plant_params.hpp"

namespace amb::model::drop { struct DropTrace; struct DropScenario; }

namespace amb::host::fit {

struct DropMeasurement {
  std::string source;                          ///< where it was read from (for messages)
  std::string rig;                             ///< board name or path of the rig
  double sample_rate_hz = 0.0;                 ///< uniform sampling, Hz
  int trigger_index = 0;                       ///< first sample of the event (e.g. the AMB switch-off)
  std::vector<std::array<double, 4>> sensor_m; ///< displacement sensors [A1, A2, B1, B2] per sample, m
  std::vector<double> speed_rad_s;             ///< rotor speed per sample, rad/s (empty: not measured)
  double speed_at_trigger_hz = 0.0;            ///< rotor speed at the trigger, Hz (> 0)
  model::PlantFaults known_faults;             ///< Phase B result, times relative to the trigger
  bool amplifiers_off = true;                  ///< the event cut all amplifier channels

  /// Empty when usable, else what is wrong.
  std::string check() const;
};

/// The drop as the fit sees it, from an event read by host-tools/core/events (load_event):
/// the four displacement channels matched to the rig's sensors, the speed channel (or
/// speed_rpm), the trigger. declared_faults: "amb_cutoff_all" (or none) is the amplifier
/// cut-off of seed 000; any other name is refused rather than ignored. Throws
/// EventLoadError naming the file and what is missing.
DropMeasurement drop_measurement_from_event(const LoadedEvent& e);

/// A drop simulated by the drop model (generators, tests, benchmarks) as the fit sees it: the
/// trace's sensor readings and spin speed and its trigger; the sample rate and the speed at the
/// trigger are the scenario's; `source` and `rig` label it.
DropMeasurement drop_measurement_from_trace(const model::drop::DropTrace& trace, const model::drop::DropScenario& scenario,
                                            std::string source, std::string rig);

/// Write a DropMeasurement as a measured event (STEM.json + STEM.csv, displacements in um,
/// speed in rpm, sensor geometry from `rig`); generators and tests.
void write_drop_measurement(const std::string& stem, const DropMeasurement& m, const model::PlantParams& rig,
                            const std::string& notes);

}  // namespace amb::host::fit
