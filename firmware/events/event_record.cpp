#include "firmware/events/event_record.hpp"

#include <cmath>

#include "firmware/bearing/bearing_task.hpp"
#include "firmware/board/board.hpp"
#include "firmware/control/axis_transform.hpp"

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

EventAnalysis event_analysis(const EventRecord& r, const board::BoardConfig& b, BearingTask& bearing) {
  EventAnalysis a;
  a.speed_source = static_cast<uint8_t>(b.tracker.speed_source);
  if (r.meta.trigger_index < r.samples.size()) {
    const LoopSample& t = r.samples[r.meta.trigger_index];
    a.speed_lost_at_trigger = speed_lost(t) || !std::isfinite(t.speed_hz);
    a.speed_confidence_at_trigger = a.speed_lost_at_trigger ? 0.0 : speed_confidence(t);
  }
  if (!bearing.configured() || r.meta.trigger_index >= r.samples.size() || !(r.meta.rate_hz > 0)) return a;
  // Rotor centre at each aux-bearing plane, from the two sensor planes (rigid-rotor straight
  // line between them), relative to the aux bearing's centre, over the post-trigger window.
  std::array<AxisTransform, 2> xf;
  for (size_t p = 0; p < 2; ++p)
    xf[p].configure({r.meta.sensors[2 * p].angle_deg, r.meta.sensors[2 * p + 1].angle_deg},
                    {r.meta.actuators[2 * p].angle_deg, r.meta.actuators[2 * p + 1].angle_deg});
  const double za = r.meta.sensors[0].axial_m, zb = r.meta.sensors[2].axial_m;
  const size_t first = r.meta.trigger_index, n = r.samples.size() - first;
  std::array<std::vector<double>, 2> x, y;
  const double spin = b.bearing.aux_spin_speed_hz > 0 ? b.bearing.aux_spin_speed_hz
                                                      : (std::isfinite(r.meta.speed_at_trigger_hz) ? r.meta.speed_at_trigger_hz : 0.0);
  a.quick_look_spin_hz = spin;
  a.aux_contact_constant_n_per_m1p5 = b.bearing.aux_contact_constant_n_per_m1p5;
  a.aux_dynamic_load_rating_n = b.bearing.aux_dynamic_load_rating_n;
  DropOrbit orbit;
  orbit.dt_s = 1.0 / r.meta.rate_hz;
  orbit.spin_hz = spin;
  for (size_t k = 0; k < 2; ++k) {
    const model::AuxBearingParams& aux = b.plant.aux[k];
    const double w = zb != za ? (aux.axial_m - za) / (zb - za) : 0.5;
    x[k].resize(n);
    y[k].resize(n);
    for (size_t i = 0; i < n; ++i) {
      const LoopSample& s = r.samples[first + i];
      const auto pa = xf[0].sensors_to_xy({s.displacement_m[0], s.displacement_m[1]});
      const auto pb = xf[1].sensors_to_xy({s.displacement_m[2], s.displacement_m[3]});
      x[k][i] = (1.0 - w) * pa[0] + w * pb[0] - aux.centre_offset_x_m;
      y[k][i] = (1.0 - w) * pa[1] + w * pb[1] - aux.centre_offset_y_m;
    }
    orbit.x_m[k] = x[k];
    orbit.y_m[k] = y[k];
    orbit.clearance_m[k] = aux.clearance_m;
  }
  std::array<DropLoadEstimate, 2> est;
  bearing.estimate_drop_loads(orbit, est);
  bool any = false;
  for (size_t k = 0; k < 2; ++k) {
    AuxQuickLook& q = a.aux[k];
    q.valid = est[k].valid;
    q.samples_in_contact = est[k].samples_in_contact;
    q.peak_force_n = est[k].peak_force_n;
    q.peak_angle_deg = est[k].peak_angle_deg;
    q.life_fraction = est[k].miner_fraction;
    q.contact_time_s = est[k].contact_time_s;
    any = any || est[k].valid;
  }
  a.quick_look_valid = any;
  return a;
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
