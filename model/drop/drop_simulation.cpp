#include "model/drop/drop_simulation.hpp"

#include <cmath>
#include <stdexcept>

namespace amb::model::drop {
namespace {

// Accumulates the steps of one record sample and (optionally) keeps contact steps.
class Recorder final : public StepObserver {
 public:
  explicit Recorder(std::vector<StepContact>* keep) : keep_(keep) {}
  void on_step(const StepContact& c) override {
    for (size_t b = 0; b < 2; ++b) {
      normal_[b] += c.normal_n[b] * c.h_s;
      friction_[b] += c.friction_n[b] * c.h_s;
      closed_[b] += c.active[b] ? c.h_s : 0.0;
    }
    span_ += c.h_s;
    if (keep_ != nullptr && (c.active[0] || c.active[1])) keep_->push_back(c);
  }
  void flush(DropSample& s) {
    for (size_t b = 0; b < 2; ++b) {
      s.normal_n[b] = span_ > 0.0 ? normal_[b] / span_ : 0.0;
      s.friction_n[b] = span_ > 0.0 ? friction_[b] / span_ : 0.0;
      s.contact_fraction[b] = span_ > 0.0 ? closed_[b] / span_ : 0.0;
    }
    normal_ = friction_ = closed_ = {};
    span_ = 0.0;
  }

 private:
  std::vector<StepContact>* keep_;
  std::array<double, 2> normal_{}, friction_{}, closed_{};
  double span_ = 0.0;
};

DropSample sample_now(const DropModel& m, double t_rel_s) {
  DropSample s;
  const DropState& st = m.state();
  s.t_s = t_rel_s;
  s.spin_rad_s = st.spin_rad_s;
  s.sensor_m = st.sensor_out_m;
  for (int b = 0; b < 2; ++b) {
    const auto p = m.aux_position_m(b);
    const size_t i = static_cast<size_t>(b);
    s.aux_x_m[i] = p[0];
    s.aux_y_m[i] = p[1];
    s.ring_rad_s[i] = st.ring_rad_s[i];
    s.ring_angle_rad[i] = st.ring_angle_rad[i];
  }
  return s;
}

}  // namespace

void levitate(DropModel& model, const DropScenario& sc) {
  if (!model.options().internal_controller) throw std::invalid_argument("levitate: the model needs its internal controller");
  if (!(sc.sample_rate_hz > 0.0)) throw std::invalid_argument("levitate: sample_rate_hz must be > 0");
  model.reset(true, sc.speed_hz);
  PlantInputs in;
  in.amplifiers_enabled = true;
  in.spin_speed_command_hz = sc.speed_hz;
  const double dt = 1.0 / sc.sample_rate_hz;
  const long n = std::lround(sc.settle_s / dt);
  for (long i = 0; i < n; ++i) model.step(dt, in);
}

DropTrace record_drop(DropModel& model, const DropScenario& sc, bool keep_contact_steps) {
  if (!(sc.sample_rate_hz > 0.0) || !(sc.window_s > 0.0)) throw std::invalid_argument("record_drop: bad rate or window");
  DropTrace tr;
  const double dt = 1.0 / sc.sample_rate_hz;
  tr.sample_period_s = dt;
  const long n_pre = std::lround(sc.pre_trigger_s / dt), n_post = std::lround(sc.window_s / dt);
  tr.samples.reserve(static_cast<size_t>(n_pre + n_post));
  Recorder rec(keep_contact_steps ? &tr.contact_steps : nullptr);
  model.set_observer(&rec);
  PlantInputs in;
  in.amplifiers_enabled = true;
  in.spin_speed_command_hz = sc.speed_hz;
  for (long i = 0; i < n_pre; ++i) {
    model.step(dt, in);
    DropSample s = sample_now(model, static_cast<double>(i + 1 - n_pre) * dt);
    rec.flush(s);
    tr.samples.push_back(s);
  }
  // Trigger: known faults (their start times are relative to the trigger) and the cut.
  PlantFaults f = sc.faults;
  const double t0 = model.state().t_s;
  f.disturbance_start_s += t0;
  f.unbalance_growth_start_s += t0;
  f.misalignment_start_s += t0;
  model.set_faults(f);
  if (sc.amplifiers_off) in.amplifiers_enabled = false;
  tr.trigger_index = static_cast<int>(tr.samples.size());
  const EnergyLedger before = model.energy_ledger();
  model.clear_counters();
  for (long i = 0; i < n_post; ++i) {
    model.step(dt, in);
    DropSample s = sample_now(model, static_cast<double>(i + 1) * dt);
    rec.flush(s);
    tr.samples.push_back(s);
  }
  model.set_observer(nullptr);
  tr.ledger = model.energy_ledger();
  tr.ledger.external_work_j -= before.external_work_j;
  tr.ledger.damping_dissipated_j -= before.damping_dissipated_j;
  tr.ledger.impact_dissipated_j -= before.impact_dissipated_j;
  tr.ledger.friction_dissipated_j -= before.friction_dissipated_j;
  tr.ledger.ring_drag_dissipated_j -= before.ring_drag_dissipated_j;
  tr.ledger.projection_energy_j -= before.projection_energy_j;
  tr.counters = model.counters();
  return tr;
}

DropTrace simulate_drop(DropModel& model, const DropScenario& sc, bool keep_contact_steps) {
  levitate(model, sc);
  return record_drop(model, sc, keep_contact_steps);
}

}  // namespace amb::model::drop
