#include "host-tools/core/replay/lifecycle_replay.hpp"

#include <cmath>

namespace amb::host::replay {

namespace {
using fw::Command;
using fw::Phase;
using fw::State;

bool energised(State s) { return s == State::levitating || s == State::running; }
bool landing_phase(Phase p) { return p == Phase::spinning_down || p == Phase::lowering; }
}  // namespace

Command command_for_transition(State ps, Phase pp, const fw::LoopSample& cur) {
  const auto cs = static_cast<State>(cur.state);
  const auto cp = static_cast<Phase>(cur.phase);
  if (ps == State::inactive && cs == State::levitating && cp == Phase::lifting) return Command::levitate;
  if (ps == State::levitating && pp == Phase::levitated && cs == State::running) return Command::run;
  if (energised(ps) && energised(cs) && !landing_phase(pp) && landing_phase(cp) &&
      (cur.flags & fw::flag_landing_request) == 0)
    return Command::land;
  if (energised(ps) && cs == State::fault && static_cast<fw::FaultReason>(cur.fault) == fw::FaultReason::emergency_stop)
    return Command::emergency_stop;
  if (ps == State::fault && cs == State::inactive) return Command::reset_fault;
  return Command::none;
}

Command command_for_transition(const fw::LoopSample& prev, const fw::LoopSample& cur) {
  return command_for_transition(static_cast<State>(prev.state), static_cast<Phase>(prev.phase), cur);
}

WarmUpResult warm_up(fw::Supervisor& sup, const fw::LoopSample& first, uint64_t max_steps) {
  WarmUpResult r;
  const auto ts = static_cast<State>(first.state);
  const auto tp = static_cast<Phase>(first.phase);
  const auto tf = static_cast<fw::FaultReason>(first.fault);
  const float target_speed = first.speed_command_hz;

  hal::AnalogInputs in{};  // centred rotor, no currents: the set-point ramps stay at zero
  hal::DiscreteInputs din{};
  hal::AnalogOutputs out{};
  hal::DiscreteOutputs dout{};
  auto step = [&] {
    sup.step(in, true, din, out, dout);
    ++r.steps;
  };
  auto matches = [&] {
    const fw::Status s = sup.status();
    if (s.state != ts || s.phase != tp || s.fault != tf) return false;
    return static_cast<float>(s.speed_command_hz) == target_speed;
  };
  auto run_until = [&](auto&& done) {
    while (r.steps < max_steps) {
      step();
      if (done(sup.status())) return true;
    }
    return false;
  };

  if (ts == State::inactive || ts == State::unconfigured) {
    r.reached = matches();
    r.note = r.reached ? "first sample inactive: no warm-up needed" : "inactive target not matched";
    return r;
  }
  sup.post(Command::levitate);
  const bool needs_levitated = tp != Phase::lifting && tp != Phase::settling;
  if (!needs_levitated) {
    run_until([&](const fw::Status&) { return matches(); });
    r.reached = matches();
    r.note = "levitate until the first sample's phase";
    return r;
  }
  if (!run_until([](const fw::Status& s) { return s.phase == Phase::levitated || s.state == State::fault; }) ||
      sup.state() == State::fault) {
    r.note = "warm-up did not reach 'levitated' with centred inputs";
    return r;
  }
  r.note = "levitate";
  if (ts == State::running || tp == Phase::spinning_up || tp == Phase::at_speed || tp == Phase::spinning_down) {
    sup.post(Command::run);
    r.note += ", run";
    // Spin up to the recorded speed command (or the operating speed when spinning down).
    const bool down = tp == Phase::spinning_down;
    run_until([&](const fw::Status& s) {
      return s.phase == Phase::at_speed || s.state == State::fault ||
             (!down && static_cast<float>(s.speed_command_hz) >= target_speed);
    });
    if (down) {
      sup.post(Command::land);
      r.note += ", land";
      step();
      if (static_cast<float>(sup.status().speed_command_hz) > target_speed)
        run_until([&](const fw::Status& s) { return static_cast<float>(s.speed_command_hz) <= target_speed; });
    }
  } else if (tp == Phase::lowering) {
    sup.post(Command::land);
    r.note += ", land";
    step();
  }
  if (ts == State::fault) {
    // Enter the safe state for the recorded reason through the firmware's own checks.
    switch (tf) {
      case fw::FaultReason::emergency_stop: sup.post(Command::emergency_stop); break;
      case fw::FaultReason::amplifier_fault: din.amplifier_fault = true; break;
      case fw::FaultReason::sensor_invalid: in.fault_bits = 1; break;
      case fw::FaultReason::orbit_limit: in.displacement_m = {1.0, 1.0, 1.0, 1.0}; break;  // far beyond any limit
      default: break;
    }
    r.note += std::string(", fault (") + fw::to_string(tf) + ")";
    run_until([](const fw::Status& s) { return s.state == State::fault; });
    in = {};
    din = {};
    step();  // one clean period after the fault, as the recorded fault is already latched
  }
  r.reached = matches();
  if (!r.reached) {
    const fw::Status s = sup.status();
    r.note += std::string("; not reached: at ") + fw::to_string(s.state) + "/" + fw::to_string(s.phase) +
              ", target " + fw::to_string(ts) + "/" + fw::to_string(tp);
  }
  return r;
}

}  // namespace amb::host::replay
