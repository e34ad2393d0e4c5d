#include "host-tools/core/events/event_json.hpp"

namespace amb::host {

nlohmann::json phase_b_json(const fw::diag::Diagnosis& d) {
  using nlohmann::json;
  json j;
  j["fault_type"] = fw::diag::to_string(d.type);
  j["confidence"] = d.confidence;
  j["summary"] = d.summary;
  json p = json::object();
  switch (d.type) {
    case fw::diag::FaultType::channel_cutoff: {
      json ch = json::array();
      for (int k = 0; k < 4; ++k)
        if (d.cutoff_channels & (1u << k)) ch.push_back(k);
      p["channels"] = ch;
      p["current_factor"] = d.current_factor;
      break;
    }
    case fw::diag::FaultType::current_disturbance:
      p["disturbance_frequency_hz"] = d.disturbance_frequency_hz;
      p["disturbance_amplitude_a_estimate"] = d.disturbance_amplitude_a;
      p["current_lead_s"] = d.current_lead_s;
      break;
    case fw::diag::FaultType::changing_unbalance:
      p["speed_hz"] = d.speed_hz;
      p["radius_1x_start_m"] = d.radius_1x_start_m;
      p["radius_1x_end_m"] = d.radius_1x_end_m;
      break;
    case fw::diag::FaultType::misalignment:
      p["direction_deg"] = d.misalignment_direction_deg;
      p["plane"] = d.misalignment_plane == 0 ? "A" : "B";
      p["centre_shift_m"] = d.centre_shift_m;
      break;
    default: break;
  }
  j["parameters"] = p;
  return j;
}

nlohmann::json event_summary_json(const LoadedEvent& e) {
  using nlohmann::json;
  json j;
  j["source"] = e.source;
  j["format"] = e.format;
  j["rig"] = e.rig;
  j["board"] = e.board;
  j["sample_rate_hz"] = e.sample_rate_hz;
  j["samples"] = e.samples();
  j["duration_s"] = e.sample_rate_hz > 0 ? static_cast<double>(e.samples()) / e.sample_rate_hz : 0.0;
  j["trigger_index"] = e.trigger_index;
  j["trigger_time_s"] = e.trigger_index < e.t_s.size() ? e.t_s[e.trigger_index] : 0.0;
  j["speed_at_trigger_hz"] = e.speed_at_trigger_hz ? json(*e.speed_at_trigger_hz) : json(nullptr);
  j["trigger_cause"] = e.trigger_cause.empty() ? json(nullptr) : json(e.trigger_cause);
  json ch = json::array();
  auto add = [&](const std::vector<LoadedChannel>& v) {
    for (const auto& c : v)
      ch.push_back({{"name", c.name}, {"quantity", c.quantity}, {"axial_m", c.axial_m}, {"angle_deg", c.angle_deg},
                    {"rig_index", c.rig_index}, {"inverted", c.inverted}});
  };
  add(e.displacement);
  add(e.current);
  add(e.current_demand);
  add(e.other);
  if (!e.speed_hz.empty()) ch.push_back({{"name", "speed"}, {"quantity", "speed"}});
  j["channels"] = ch;
  j["declared_faults"] = e.declared_faults;
  j["phase_b"] = e.phase_b ? phase_b_json(*e.phase_b) : json(nullptr);
  j["warnings"] = e.warnings;
  j["notes"] = e.notes;
  return j;
}

}  // namespace amb::host
