#pragma once
// An event as every host tool sees it, whatever file it came from: SI channels with their
// positions on the rig, the sample rate, the trigger, and what is known about the fault.
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/diagnosis/phase_b.hpp"

namespace amb::host {

/// One measured channel in SI units.
struct LoadedChannel {
  std::string name;           ///< CSV column, or "A1".."B2" for board events
  std::string quantity;       ///< "displacement", "current", "acceleration" or "voltage"
  double axial_m = 0.0;       ///< axial position from the rotor's left end, m
  double angle_deg = 0.0;     ///< direction from the upward vertical towards +x, deg
  /// Matched rig element: sensor index 0..3 for displacement, actuator axis 0..3 for
  /// current; -1 when nothing on the rig is within the board's tolerance.
  int rig_index = -1;
  bool inverted = false;      ///< matched an element pointing the opposite way; values negated to its direction
  std::vector<double> values; ///< m, A, m/s^2 or V
};

struct LoadedEvent {
  std::string source;                 ///< the path it was loaded from
  std::string format;                 ///< "AMBE/1".."AMBE/3" (board event) or "amb-measured-event/1"
  std::string rig;                    ///< rig name
  std::string board;                  ///< board name (board event) or the board the rig resolved to
  double sample_rate_hz = 0.0;        ///< Hz, uniform
  size_t trigger_index = 0;           ///< 0-based sample where the event starts
  std::vector<double> t_s;            ///< time of each sample from the first, s
  std::vector<LoadedChannel> displacement;
  std::vector<LoadedChannel> current;         ///< measured control currents
  std::vector<LoadedChannel> current_demand;  ///< board events only: demands, A
  std::vector<LoadedChannel> other;           ///< acceleration, voltage
  std::vector<double> speed_hz;               ///< rotor speed per sample, Hz; empty when not recorded
  /// Board events: what speed_hz is ("tachometer": the event's tach channel, AMBE v3 on a rig
  /// with one; "board speed estimate": the board's speed source, NaN where it was lost).
  std::string speed_channel;
  /// Board events with a tachometer channel: the board's own speed estimate (its speed source,
  /// e.g. the tracker; NaN where lost), Hz; empty otherwise.
  std::vector<double> speed_estimate_hz;
  std::optional<double> speed_at_trigger_hz;  ///< Hz
  std::vector<std::string> declared_faults;   ///< from the sidecar; empty for board events
  std::optional<fw::diag::Diagnosis> phase_b; ///< the board's Phase B result, if present
  std::string trigger_cause;                  ///< board events: the Phase A cause name
  std::string notes;
  std::vector<std::string> warnings;          ///< e.g. channels not matched to the rig
  size_t samples() const { return t_s.size(); }
};

/// A file that cannot be imported. what() names the file and the row or field and says what
/// was expected.
class EventLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace amb::host
