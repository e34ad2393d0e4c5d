#include "firmware/events/event_record.hpp"

#include "firmware/board/board.hpp"

namespace amb::fw {

EventRecord make_event_record(const FrozenEvent& e, const board::BoardConfig& b, uint64_t event_number) {
  EventRecord r;
  const FrozenEventHeader& h = e.header;
  EventMetadata& m = r.meta;
  m.board_name = b.name;
  m.rig_name = b.plant.rig_name;
  m.firmware_version = k_firmware_version;
  m.board_source = b.source;
  m.event_number = event_number;
  m.capture_number = h.capture_number;
  m.rate_hz = b.rate_hz;
  m.pre_trigger_s = b.capture.pre_trigger_s;
  m.post_trigger_s = b.capture.post_trigger_s;
  m.cause = h.cause;
  m.cause_mask = h.cause_mask;
  m.cutoff_channels = h.cutoff_channels;
  m.trigger_index = h.trigger_index;
  m.trigger_seq = h.trigger_seq;
  m.trigger_t_ns = h.trigger_t_ns;
  m.speed_at_trigger_hz = h.speed_at_trigger_hz;
  m.first_t_ns = h.first_t_ns;
  m.last_t_ns = h.last_t_ns;
  m.events_lost_before = h.events_lost_before;
  m.kp_n_per_m = b.controller.kp_n_per_m;
  m.ki_n_per_m_s = b.controller.ki_n_per_m_s;
  m.kd_n_s_per_m = b.controller.kd_n_s_per_m;
  m.derivative_filter_hz = b.controller.derivative_filter_hz;
  m.integrator_limit_n = b.controller.integrator_limit_n;
  m.current_limit_a = b.controller.current_limit_a;
  for (size_t i = 0; i < 4; ++i) {
    m.sensors[i] = {b.plant.sensor[i].axial_m, b.plant.sensor[i].angle_deg};
    const auto& amb = b.plant.amb[i / 2];
    m.actuators[i] = {amb.axial_m, amb.actuator_angle_deg[i % 2], amb.ki_n_per_a};
  }
  m.orbit_trigger_limit_m = b.capture.triggers.orbit.enabled ? b.capture.triggers.orbit.limit_m : 0.0;
  m.current_trigger_limit_a = b.capture.triggers.current.enabled ? b.capture.triggers.current.limit_a : 0.0;
  r.samples.assign(e.samples.begin(), e.samples.begin() + h.sample_count);
  // Gaps in the pre-trigger part are only visible here (the loop copied it from the ring).
  uint32_t gaps = 0;
  for (size_t i = 1; i < r.samples.size(); ++i)
    if (r.samples[i].seq != r.samples[i - 1].seq + 1) ++gaps;
  m.seq_gaps = gaps;
  return r;
}

diag::DiagnosisInput diagnosis_input(const EventRecord& r) {
  diag::DiagnosisInput in;
  in.samples = r.samples;
  in.trigger_index = r.meta.trigger_index;
  in.rate_hz = r.meta.rate_hz;
  for (size_t i = 0; i < 4; ++i) in.sensor_angle_deg[i] = r.meta.sensors[i].angle_deg;
  return in;
}

}  // namespace amb::fw
