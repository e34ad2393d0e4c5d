#pragma once
// The AMBE metadata block's field list (616 bytes, docs/event-format.md), written once for the
// drop event codec and the sweep event codec (byte_codec.hpp: Coder is ByteWriter or ByteReader).
#include "firmware/events/event_record.hpp"

namespace amb::fw {

template <class Coder, class Meta>
void meta_fields(Coder& c, Meta& m) {
  c.text(m.board_name, 64, 64);
  c.text(m.rig_name, 64, 64);
  c.text(m.firmware_version, 32, 32);
  c.text(m.board_source, 128, 128);
  c.u64(m.event_number);
  c.u64(m.capture_number);
  c.f64(m.rate_hz);
  c.f64(m.pre_trigger_s);
  c.f64(m.post_trigger_s);
  c.u8_of(m.cause);
  c.u8(m.cutoff_channels);
  c.zeros(2);
  c.u32(m.cause_mask);
  c.u32(m.trigger_index);
  c.u32(m.seq_gaps);
  c.u64(m.trigger_seq);
  c.i64(m.trigger_t_ns);
  c.f64(m.speed_at_trigger_hz);
  c.i64(m.first_t_ns);
  c.i64(m.last_t_ns);
  c.u64(m.events_lost_before);
  c.f64(m.kp_n_per_m);
  c.f64(m.ki_n_per_m_s);
  c.f64(m.kd_n_s_per_m);
  c.f64(m.derivative_filter_hz);
  c.f64(m.integrator_limit_n);
  c.f64(m.current_limit_a);
  for (auto& s : m.sensors) { c.f64(s.axial_m); c.f64(s.angle_deg); }
  for (auto& a : m.actuators) { c.f64(a.axial_m); c.f64(a.angle_deg); c.f64(a.ki_n_per_a); }
  c.f64(m.orbit_trigger_limit_m);
  c.f64(m.current_trigger_limit_a);
}

}  // namespace amb::fw
