#include "host-tools/core/events/board_event_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "firmware/board/board.hpp"
#include "firmware/events/event_codec.hpp"

namespace amb::host {

bool is_board_event_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char m[4] = {};
  in.read(m, 4);
  return in.gcount() == 4 && m[0] == 'A' && m[1] == 'M' && m[2] == 'B' && m[3] == 'E';
}

fw::EventRecord read_board_event(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw EventLoadError(path + ": cannot open");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fw::EventRecord r;
  std::string error;
  if (!fw::decode_event(bytes, r, error)) throw EventLoadError(path + ": " + error);
  return r;
}

LoadedEvent to_loaded_event(const fw::EventRecord& r, const std::string& source) {
  LoadedEvent e;
  const auto& m = r.meta;
  e.source = source;
  e.format = "AMBE/" + std::to_string(r.format_version != 0 ? r.format_version : fw::k_event_format_version);
  e.rig = m.rig_name;
  e.board = m.board_name;
  e.sample_rate_hz = m.rate_hz;
  e.trigger_index = m.trigger_index;
  e.trigger_cause = fw::to_string(m.cause);
  // A lost speed (NaN) stays absent: never presented as a value.
  if (std::isfinite(m.speed_at_trigger_hz)) e.speed_at_trigger_hz = m.speed_at_trigger_hz;
  const size_t n = r.samples.size();
  static const char* names[4] = {"A1", "A2", "B1", "B2"};
  for (size_t k = 0; k < 4; ++k) {
    LoadedChannel d{names[k], "displacement", m.sensors[k].axial_m, m.sensors[k].angle_deg, static_cast<int>(k), false, {}};
    LoadedChannel c{names[k], "current", m.actuators[k].axial_m, m.actuators[k].angle_deg, static_cast<int>(k), false, {}};
    LoadedChannel q = c;
    q.quantity = "current_demand";
    d.values.resize(n);
    c.values.resize(n);
    q.values.resize(n);
    for (size_t i = 0; i < n; ++i) {
      d.values[i] = r.samples[i].displacement_m[k];
      c.values[i] = r.samples[i].coil_current_a[k];
      q.values[i] = r.samples[i].current_demand_a[k];
    }
    e.displacement.push_back(std::move(d));
    e.current.push_back(std::move(c));
    e.current_demand.push_back(std::move(q));
  }
  e.t_s.resize(n);
  for (size_t i = 0; i < n; ++i) e.t_s[i] = static_cast<double>(r.samples[i].t_ns - r.samples.front().t_ns) * 1e-9;
  // The rotor speed: the tachometer channel when the event recorded one (AMBE v3, a rig with a
  // tachometer: tach_hz >= 0 or NaN on every sample), whatever source stamped the board's
  // estimate; else the board's estimate (tracker or command; NaN where it was lost). With a
  // tachometer the board's estimate is kept beside it (speed_estimate_hz).
  const bool tach = n > 0 && std::all_of(r.samples.begin(), r.samples.end(),
                                         [](const fw::LoopSample& s) { return !(s.tach_hz < 0.0f); });
  e.speed_hz.resize(n);
  for (size_t i = 0; i < n; ++i) e.speed_hz[i] = tach ? r.samples[i].tach_hz : r.samples[i].speed_hz;
  if (tach) {
    e.speed_channel = "tachometer";
    e.speed_estimate_hz.resize(n);
    for (size_t i = 0; i < n; ++i) e.speed_estimate_hz[i] = r.samples[i].speed_hz;
  } else if (n > 0) {
    e.speed_channel = "board speed estimate";
  }
  if (r.has_diagnosis) e.phase_b = r.diagnosis;
  if (r.has_analysis && r.analysis.speed_lost_at_trigger)
    e.warnings.push_back(std::string("the board's speed estimate (source ") +
                         fw::to_string(static_cast<fw::SpeedSource>(r.analysis.speed_source)) + ") was lost at the trigger");
  if (m.seq_gaps) e.warnings.push_back(std::to_string(m.seq_gaps) + " gaps in the sample sequence");
  e.notes = "board " + m.board_name + ", " + m.firmware_version + ", event " + std::to_string(m.event_number) +
            ", trigger " + fw::to_string(m.cause);
  if (r.has_analysis) {
    const fw::EventAnalysis& a = r.analysis;
    char buf[160];
    std::snprintf(buf, sizeof buf, ", speed source %s (confidence %.2f at the trigger%s)",
                  fw::to_string(static_cast<fw::SpeedSource>(a.speed_source)), a.speed_confidence_at_trigger,
                  a.speed_lost_at_trigger ? ", lost" : "");
    e.notes += buf;
  }
  if (!e.speed_channel.empty()) e.notes += "; speed channel: " + e.speed_channel;
  return e;
}

}  // namespace amb::host
