#include "firmware/app/supervisor.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "model/rotor/rotor_model.hpp"

namespace amb::fw {

const char* to_string(State s) {
  switch (s) {
    case State::unconfigured: return "unconfigured";
    case State::inactive: return "inactive";
    case State::levitating: return "levitating";
    case State::running: return "running";
    case State::fault: return "fault";
  }
  return "?";
}

const char* to_string(Command c) {
  switch (c) {
    case Command::none: return "none";
    case Command::levitate: return "levitate";
    case Command::run: return "run";
    case Command::land: return "land";
    case Command::reset_fault: return "reset_fault";
    case Command::emergency_stop: return "emergency_stop";
  }
  return "?";
}

const char* to_string(FaultReason r) {
  switch (r) {
    case FaultReason::none: return "none";
    case FaultReason::orbit_limit: return "orbit_limit";
    case FaultReason::amplifier_fault: return "amplifier_fault";
    case FaultReason::sensor_invalid: return "sensor_invalid";
    case FaultReason::emergency_stop: return "emergency_stop";
    case FaultReason::comm_timeout: return "comm_timeout";
    case FaultReason::overrun: return "overrun";
  }
  return "?";
}

const char* to_string(Phase p) {
  switch (p) {
    case Phase::idle: return "idle";
    case Phase::lifting: return "lifting";
    case Phase::settling: return "settling";
    case Phase::levitated: return "levitated";
    case Phase::spinning_up: return "spinning_up";
    case Phase::at_speed: return "at_speed";
    case Phase::spinning_down: return "spinning_down";
    case Phase::lowering: return "lowering";
  }
  return "?";
}

void Supervisor::configure(const board::BoardConfig& board) {
  board_ = board;
  dt_s_ = 1.0 / board.rate_hz;
  for (int b = 0; b < 2; ++b) {
    const auto& amb = board.plant.amb[static_cast<size_t>(b)];
    ki_n_per_a_[static_cast<size_t>(b)] = amb.ki_n_per_a;
    law_[static_cast<size_t>(b)] = model::magnet::make_axis_law(amb);
    for (size_t a = 0; a < 2; ++a) act_dir_[static_cast<size_t>(b)][a] = model::magnet::axis_direction(amb.actuator_angle_deg[a]);
    xf_[static_cast<size_t>(b)].configure(
        {board.plant.sensor[static_cast<size_t>(2 * b)].angle_deg,
         board.plant.sensor[static_cast<size_t>(2 * b + 1)].angle_deg},
        amb.actuator_angle_deg);
  }
  // The weight each AMB carries (rigid-rotor lever rule about the two actuator planes);
  // the y integrators start there so lift-off does not wait for them to wind up.
  {
    const model::rotor::RotorModel rotor = model::rotor::build_rotor_model(board.plant.rotor);
    const double w = rotor.mass_kg * board.plant.gravity_m_s2;
    const double a = board.plant.amb[0].axial_m, c = board.plant.amb[1].axial_m;
    const double share_b = (c != a) ? w * (rotor.centre_of_mass_m - a) / (c - a) : 0.5 * w;
    weight_share_n_ = {w - share_b, share_b};
  }
  if (board.controller.current_limit_a <= 0.0) throw std::invalid_argument("current limit must be > 0");
  {
    // The sweep: amplitude against plane A's bias current, abort radius a fraction of the
    // smaller aux-bearing clearance. A plan that cannot run is refused at start, not here.
    const double clearance = std::min(board.plant.aux[0].clearance_m, board.plant.aux[1].clearance_m);
    sweep_error_ = sweep_.configure(board.sweep, board.rate_hz, board.plant.amb[0].bias_current_a,
                                    board.sweep.abort_clearance_fraction * clearance);
  }
  reset();
}

void Supervisor::reset() {
  for (int b = 0; b < 2; ++b)
    for (int a = 0; a < 2; ++a)
      // The PID acts in x/y force; its force limit is what one actuator axis can deliver.
      pid_[static_cast<size_t>(2 * b + a)].configure(board_.controller, board_.rate_hz, ki_n_per_a_[static_cast<size_t>(b)]);
  state_ = State::inactive;
  phase_ = Phase::idle;
  fault_ = FaultReason::none;
  counters_ = {};
  ref_m_ = {};
  speed_cmd_hz_ = 0.0;
  step_count_ = 0;
  seq_ = 0;
  pending_.store(0);
  tracked_packed_.store(0);
  tracked_publish_count_ = 0;
  tracked_seen_update_ = 0;
  tracked_updates_seen_ = 0;
  tracked_age_steps_ = 0;
  driven_ = false;
  tracked_predates_stop_ = false;
  stale_steps_ = static_cast<uint64_t>(std::ceil(board_.tracker.stale_after_s * board_.rate_hz));
  sweep_.reset();
  status_ = {};
  status_.state = state_;
  published_.store(status_);
}

void Supervisor::publish_tracked_speed(double speed_hz, double confidence, bool lost) {
  const bool ok = !lost && std::isfinite(speed_hz);
  const float f = ok ? static_cast<float>(speed_hz) : 0.0f;
  uint32_t bits = 0;
  std::memcpy(&bits, &f, sizeof bits);
  const double c = std::isfinite(confidence) ? std::clamp(confidence, 0.0, 1.0) : 0.0;
  if (++tracked_publish_count_ == 0) tracked_publish_count_ = 1;  // 0 means "never published"
  const uint64_t packed = static_cast<uint64_t>(bits) | (static_cast<uint64_t>(std::lround(c * 100.0)) << 32) |
                          (static_cast<uint64_t>(ok ? 0u : 1u) << 40) |
                          (static_cast<uint64_t>(tracked_publish_count_) << 48);
  tracked_packed_.store(packed, std::memory_order_release);
}

SweepRefusal Supervisor::sweep_start_refusal() const {
  if (sweep_.config_refusal() != SweepRefusal::none) return sweep_.config_refusal();
  const Status st = status();
  if (st.sweep.state != SweepState::idle) return SweepRefusal::busy;
  if (st.state == State::fault) return SweepRefusal::fault;
  if (st.phase != Phase::levitated && st.phase != Phase::at_speed) return SweepRefusal::not_levitated;
  return SweepRefusal::none;
}

bool Supervisor::post(Command c) {
  uint8_t expected = 0;
  return pending_.compare_exchange_strong(expected, static_cast<uint8_t>(c), std::memory_order_acq_rel);
}

void Supervisor::enter_safe_state(FaultReason reason) {
  if (state_ != State::fault) ++counters_.safe_state_entries;
  state_ = State::fault;
  fault_ = reason;
  phase_ = Phase::idle;
  speed_cmd_hz_ = 0.0;
}

void Supervisor::handle_command(Command c) {
  bool accepted = true;
  switch (c) {
    case Command::none: break;
    case Command::levitate:
      if (state_ == State::inactive) {
        state_ = State::levitating;
        set_phase(Phase::lifting);
        const auto& s = status_.xy_m;
        touchdown_m_ = s;
        ref_m_ = s;
        for (auto& pid : pid_) pid.reset();
        pid_[1].preload_force(weight_share_n_[0]);
        pid_[3].preload_force(weight_share_n_[1]);
      } else {
        accepted = false;
      }
      break;
    case Command::run:
      if (state_ == State::levitating && phase_ == Phase::levitated) {
        state_ = State::running;
        set_phase(Phase::spinning_up);
      } else {
        accepted = false;
      }
      break;
    case Command::land:
      if (state_ == State::running) {
        set_phase(Phase::spinning_down);
      } else if (state_ == State::levitating && phase_ != Phase::lowering) {
        set_phase(Phase::lowering);
      } else {
        accepted = false;
      }
      break;
    case Command::reset_fault:
      if (state_ == State::fault) {
        state_ = State::inactive;
        fault_ = FaultReason::none;
        phase_ = Phase::idle;
      } else {
        accepted = false;
      }
      break;
    case Command::emergency_stop:
      if (state_ == State::levitating || state_ == State::running) enter_safe_state(FaultReason::emergency_stop);
      else accepted = false;
      break;
  }
  if (!accepted) ++counters_.rejected_commands;
}

void Supervisor::step(const hal::AnalogInputs& in, bool in_ok, const hal::DiscreteInputs& din,
                      hal::AnalogOutputs& out, hal::DiscreteOutputs& dout) {
  ++step_count_;
  phase_t_s_ += dt_s_;
  const bool active_before = state_ == State::levitating || state_ == State::running;

  // Inputs: keep the last good position when a sample is missing.
  if (!in_ok) {
    ++counters_.read_failures;
    if (++consecutive_read_failures_ > board_.lifecycle.max_missed_samples && active_before)
      enter_safe_state(FaultReason::sensor_invalid);
  } else {
    consecutive_read_failures_ = 0;
    if (in.fault_bits != 0) {
      ++counters_.sensor_fault_samples;
      if (active_before) enter_safe_state(FaultReason::sensor_invalid);
    }
    for (size_t b = 0; b < 2; ++b) {
      const auto xy = xf_[b].sensors_to_xy({in.displacement_m[2 * b], in.displacement_m[2 * b + 1]});
      status_.xy_m[2 * b] = xy[0];
      status_.xy_m[2 * b + 1] = xy[1];
    }
  }

  const Command cmd = static_cast<Command>(pending_.exchange(0, std::memory_order_acq_rel));
  if (cmd != Command::none) handle_command(cmd);
  const bool active = state_ == State::levitating || state_ == State::running;
  if (active && din.amplifier_fault) enter_safe_state(FaultReason::amplifier_fault);
  if (active && din.landing_request && phase_ != Phase::spinning_down && phase_ != Phase::lowering)
    handle_command(Command::land);

  const auto& lc = board_.lifecycle;
  for (size_t b = 0; b < 2; ++b)
    status_.orbit_radius_m[b] = std::hypot(status_.xy_m[2 * b] - ref_m_[2 * b],
                                           status_.xy_m[2 * b + 1] - ref_m_[2 * b + 1]);
  // Set-point and speed schedule of the lifecycle phases.
  switch (phase_) {
    case Phase::lifting: {
      const double s = lc.liftoff_ramp_s > 0.0 ? std::min(1.0, phase_t_s_ / lc.liftoff_ramp_s) : 1.0;
      for (size_t i = 0; i < 4; ++i) ref_m_[i] = touchdown_m_[i] * (1.0 - s);
      if (s >= 1.0) set_phase(Phase::settling);
      break;
    }
    case Phase::settling: {
      // Levitated once the orbit has stayed within the tolerance for settle_s (the
      // integrator may need a while to take the weight).
      const double r = std::max(status_.orbit_radius_m[0], status_.orbit_radius_m[1]);
      if (r > lc.settle_tolerance_m) phase_t_s_ = 0.0;
      if (phase_t_s_ >= lc.settle_s) set_phase(Phase::levitated);
      break;
    }
    case Phase::spinning_up:
      speed_cmd_hz_ = std::min(lc.operating_speed_hz, speed_cmd_hz_ + lc.spin_accel_hz_per_s * dt_s_);
      if (speed_cmd_hz_ >= lc.operating_speed_hz) set_phase(Phase::at_speed);
      break;
    case Phase::spinning_down:
      speed_cmd_hz_ = std::max(0.0, speed_cmd_hz_ - lc.spin_accel_hz_per_s * dt_s_);
      if (speed_cmd_hz_ <= 0.0) {
        state_ = State::levitating;
        set_phase(Phase::lowering);
      }
      break;
    case Phase::lowering: {
      const double s = lc.landing_ramp_s > 0.0 ? std::min(1.0, phase_t_s_ / lc.landing_ramp_s) : 1.0;
      for (size_t i = 0; i < 4; ++i) ref_m_[i] = touchdown_m_[i] * s;
      if (s >= 1.0) {
        state_ = State::inactive;
        phase_ = Phase::idle;
      }
      break;
    }
    default: break;
  }

  // Orbit supervision once the rotor is meant to be centred.
  const bool centred = phase_ == Phase::settling || phase_ == Phase::levitated ||
                       phase_ == Phase::spinning_up || phase_ == Phase::at_speed ||
                       phase_ == Phase::spinning_down;
  for (size_t b = 0; b < 2; ++b) {
    if (centred && (state_ == State::levitating || state_ == State::running) &&
        status_.orbit_radius_m[b] > lc.max_orbit_fault_m)
      enter_safe_state(FaultReason::orbit_limit);
  }

  // Control: PID per axis in the bearing frame, then to actuator axes and currents.
  const bool energised = state_ == State::levitating || state_ == State::running;
  bool saturated = false;
  for (size_t b = 0; b < 2; ++b) {
    std::array<double, 2> ic{0.0, 0.0};
    if (energised) {
      bool sx = false, sy = false;
      const double fx = pid_[2 * b].step(status_.xy_m[2 * b], ref_m_[2 * b], sx);
      const double fy = pid_[2 * b + 1].step(status_.xy_m[2 * b + 1], ref_m_[2 * b + 1], sy);
      const auto f = xf_[b].xy_to_actuators({fx, fy});
      const double lim = board_.controller.current_limit_a;
      for (size_t a = 0; a < 2; ++a) {
        // Set-point feed-forward: the current at which the bias flux pulls with zero force
        // where the rotor is meant to be. Without it, energising with the rotor on its
        // touchdown bearing pulls it into the bearing (about 1.5 kN on the Bath rig) and the
        // integrator has to unwind that pull along the lift-off and landing ramps.
        const double z = act_dir_[b][a][0] * ref_m_[2 * b] + act_dir_[b][a][1] * ref_m_[2 * b + 1];
        ic[a] = f[a] / ki_n_per_a_[b] + model::magnet::zero_force_current_a(law_[b], z);
        if (std::abs(ic[a]) > lim) {
          ic[a] = std::copysign(lim, ic[a]);
          sx = true;
        }
      }
      saturated = saturated || sx || sy;
    }
    out.current_demand_a[2 * b] = ic[0];
    out.current_demand_a[2 * b + 1] = ic[1];
  }
  // Loop-sensitivity sweep: while idle with no request, two flag reads (quiet()) and nothing
  // else; the excitation goes onto the demand the controller has just formed.
  if (!sweep_.quiet()) step_sweep(in.t_ns, out);
  if (saturated) ++counters_.saturated_steps;
  if (!energised) speed_cmd_hz_ = 0.0;
  out.amplifiers_enabled = energised;
  out.spin_speed_command_hz = speed_cmd_hz_;

  watchdog_ = (state_ != State::fault) ? !watchdog_ : watchdog_;
  dout.amplifier_enable = energised;
  dout.watchdog = watchdog_;
  dout.status_ok = state_ != State::fault;

  // Tracked speed: take the analysis thread's newest update and age it in loop periods.
  const uint64_t packed = tracked_packed_.load(std::memory_order_acquire);
  const auto update = static_cast<uint16_t>(packed >> 48);
  bool new_update = false;
  if (update != tracked_seen_update_) {
    tracked_seen_update_ = update;
    tracked_age_steps_ = 0;
    ++tracked_updates_seen_;
    new_update = true;
  } else {
    ++tracked_age_steps_;
  }
  // The drive stopped (safe state, landing): the rotor coasts from here - after a drop it
  // slows by a fifth within tens of ms on its touchdown bearings - so an estimate made while it
  // was driven no longer holds. Not tracked until the analysis thread publishes a new update
  // (it accepts only windows wholly after the stop, AnalysisTask).
  const bool driven = speed_cmd_hz_ > 0.0;
  if (driven_ && !driven) tracked_predates_stop_ = true;
  driven_ = driven;
  if (new_update) tracked_predates_stop_ = false;
  TrackedSpeedView& tv = status_.tracked;
  {
    const auto bits = static_cast<uint32_t>(packed);
    float f = 0.0f;
    std::memcpy(&f, &bits, sizeof f);
    const bool published = update != 0;
    tv.stale = published && tracked_age_steps_ > stale_steps_;
    tv.lost = !published || ((packed >> 40) & 1u) != 0 || tv.stale || !std::isfinite(f) || tracked_predates_stop_;
    tv.speed_hz = tv.lost ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(f);
    tv.confidence = (published && !tv.stale && !tracked_predates_stop_) ? static_cast<double>((packed >> 32) & 0xFFu) / 100.0 : 0.0;
    tv.age_s = static_cast<double>(tracked_age_steps_) * dt_s_;
    tv.updates = tracked_updates_seen_;
  }
  // Tracker vs tachometer, once per tracker update while both are valid.
  const double tach = in.tach_speed_hz;
  if (new_update && !tv.lost && tach > 0.0 &&
      std::abs(tv.speed_hz - tach) > board_.tracker.tach_disagreement_fraction * tach)
    ++counters_.speed_disagreements;

  // Speed estimate per the board's speed source. A lost tracker gives NaN and the lost flag,
  // never the last good value.
  double speed = speed_cmd_hz_;
  double speed_conf = 1.0;
  bool speed_lost = false;
  switch (board_.tracker.speed_source) {
    case SpeedSource::tach:
      // A tachometer if the rig has one (NaN: present but invalid), else the tracker, else the command.
      if (!(tach < 0.0)) {
        speed = tach;
        speed_lost = std::isnan(tach);
      } else if (!tv.lost) {
        speed = tv.speed_hz;
        speed_conf = tv.confidence;
      }
      break;
    case SpeedSource::tracker:
      speed = tv.speed_hz;
      speed_conf = tv.confidence;
      speed_lost = tv.lost;
      break;
    case SpeedSource::command: break;
  }
  if (speed_lost) {
    speed = std::numeric_limits<double>::quiet_NaN();
    ++counters_.speed_lost_periods;
  }

  sample_.seq = seq_++;
  sample_.t_ns = in.t_ns;
  for (size_t i = 0; i < 4; ++i) {
    sample_.displacement_m[i] = static_cast<float>(in.displacement_m[i]);
    sample_.coil_current_a[i] = static_cast<float>(in.coil_current_a[i]);
    sample_.current_demand_a[i] = static_cast<float>(out.current_demand_a[i]);
  }
  sample_.speed_hz = static_cast<float>(speed);
  sample_.speed_command_hz = static_cast<float>(speed_cmd_hz_);
  sample_.tach_hz = static_cast<float>(tach);
  sample_.speed_quality = pack_speed_quality(speed_conf, speed_lost);
  sample_.state = static_cast<uint8_t>(state_);
  sample_.phase = static_cast<uint8_t>(phase_);
  sample_.fault = static_cast<uint8_t>(fault_);
  sample_.flags = (energised ? flag_amplifiers_enabled : 0u) | (saturated ? flag_saturated : 0u) |
                  (!in_ok ? flag_read_failed : 0u) |
                  ((phase_ == Phase::levitated || phase_ == Phase::spinning_up || phase_ == Phase::at_speed) ? flag_levitated : 0u) |
                  (state_ == State::fault ? flag_fault : 0u) |
                  (din.landing_request ? flag_landing_request : 0u) |
                  (din.external_trigger ? flag_external_trigger : 0u) |
                  (din.amplifier_fault ? flag_amplifier_fault : 0u);

  status_.t_ns = in.t_ns;
  status_.step = step_count_;
  status_.state = state_;
  status_.phase = phase_;
  status_.fault = fault_;
  status_.current_demand_a = out.current_demand_a;
  status_.speed_command_hz = speed_cmd_hz_;
  status_.speed_estimate_hz = speed;
  status_.speed_confidence = speed_lost ? 0.0 : speed_conf;
  status_.speed_lost = speed_lost;
  status_.tach_speed_hz = tach;
  status_.counters = counters_;
  published_.store(status_);
}

__attribute__((noinline)) void Supervisor::step_sweep(int64_t t_ns, hal::AnalogOutputs& out) {
  // The excitation e of this period and the axis it goes to (none unless levitated or at
  // speed, not in fault, orbit inside the abort radius). Levitated implies energised, so an
  // excited axis always has a demand formed by the controller this period.
  SweepInputs sweep_in;
  sweep_in.levitated = (phase_ == Phase::levitated || phase_ == Phase::at_speed) &&
                       (state_ == State::levitating || state_ == State::running);
  sweep_in.fault = state_ == State::fault;
  sweep_in.orbit_max_m = std::max(status_.orbit_radius_m[0], status_.orbit_radius_m[1]);
  sweep_in.t_ns = t_ns;
  sweep_in.seq = seq_;
  sweep_in.speed_hz = speed_cmd_hz_;
  int axis = -1;
  const double excitation_a = sweep_.begin_step(sweep_in, axis);
  if (axis >= 0 && axis < 4) {
    // The summing point: u = u_c + e, u_c the demand after the controller's limit, u limited
    // like any demand; y is the position reading along this actuator axis in the
    // controller's frame.
    const auto b = static_cast<size_t>(axis / 2), a = static_cast<size_t>(axis % 2);
    const double lim = board_.controller.current_limit_a;
    const double uc = out.current_demand_a[static_cast<size_t>(axis)];
    const double u = std::clamp(uc + excitation_a, -lim, lim);
    out.current_demand_a[static_cast<size_t>(axis)] = u;
    const double y = act_dir_[b][a][0] * status_.xy_m[2 * b] + act_dir_[b][a][1] * status_.xy_m[2 * b + 1];
    sweep_.end_step(uc, u, y);
  }
  sweep_.publish_status();
}

}  // namespace amb::fw
