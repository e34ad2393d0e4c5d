#include "firmware/fieldbus/field_bus_front_end.hpp"

namespace amb::fieldbus {

FieldBusFrontEnd::FieldBusFrontEnd(hal::CanBus& bus, hal::Clock& clock, const comms::CanParams& p,
                                   fw::Supervisor* supervisor)
    : bus_(bus),
      clock_(clock),
      sup_(supervisor),
      ids_{p.board_node_id, p.sensor_node_id, p.amplifier_node_id},
      fd_(p.fd),
      node_timeout_ns_(static_cast<int64_t>(p.node_timeout_ms) * 1'000'000),
      heartbeat_period_ns_(static_cast<int64_t>(p.heartbeat_period_ms) * 1'000'000) {
  last_.tach_speed_hz = -1.0;
}

bool FieldBusFrontEnd::read(hal::AnalogInputs& in) {
  const int64_t now = clock_.now_ns();
  bool fresh = false;
  hal::CanFrame f;
  Message m;
  for (int i = 0; i < k_max_frames_per_read && bus_.receive(f); ++i) {
    if (f.error) {
      bump(error_frames_);
      continue;
    }
    switch (decode(f, ids_, Side::board, m)) {
      case DecodeResult::malformed: bump(malformed_); continue;
      case DecodeResult::foreign: bump(foreign_); continue;
      case DecodeResult::ok: break;
    }
    if (m.node == ids_.sensor) last_sensor_ns_ = now;
    if (m.node == ids_.amplifier) last_amp_ns_ = now;
    switch (m.kind) {
      case Kind::position:
        last_.displacement_m = m.displacement_m;
        last_.fault_bits = (last_.fault_bits & ~0x0Fu) | (m.fault_bits & 0x0Fu);
        fresh = true;
        bump(samples_);
        break;
      case Kind::current:
        last_.coil_current_a = m.current_a;
        break;
      case Kind::sample_fd:
        last_.displacement_m = m.displacement_m;
        last_.coil_current_a = m.current_a;
        last_.tach_speed_hz = m.speed_hz;
        last_.fault_bits = m.fault_bits & 0x0Fu;  // sensor channels; current faults are not sensor faults
        fresh = true;
        bump(samples_);
        break;
      case Kind::amp_status: {
        const bool fault = (m.flags & (amp_fault | amp_overtemp | amp_undervolt)) != 0;
        if (fault && !amp_fault_.load(std::memory_order_relaxed)) bump(amp_faults_);
        amp_fault_.store(fault, std::memory_order_relaxed);
        break;
      }
      default:
        break;  // heartbeats only refresh the node's last-heard time
    }
  }
  // Node supervision: silence longer than the timeout (or never heard) while the rotor is
  // off the touchdown bearings goes to the safe state, once per loss.
  const bool sensor_ok = last_sensor_ns_ >= 0 && now - last_sensor_ns_ <= node_timeout_ns_;
  const bool amp_ok = last_amp_ns_ >= 0 && now - last_amp_ns_ <= node_timeout_ns_;
  const bool alive = sensor_ok && amp_ok;
  nodes_alive_.store(alive, std::memory_order_relaxed);
  if (!alive) {
    // Count a loss once, when a node that was heard goes silent.
    if (!timed_out_ && (last_sensor_ns_ >= 0 || last_amp_ns_ >= 0)) {
      timed_out_ = true;
      bump(timeouts_);
    }
    if (sup_) {
      const fw::State s = sup_->state();
      if (s == fw::State::levitating || s == fw::State::running) sup_->enter_safe_state(fw::FaultReason::comm_timeout);
    }
  } else {
    timed_out_ = false;
  }
  if (!fresh) bump(stale_);
  last_.t_ns = now;
  in = last_;
  return fresh && sensor_ok;
}

void FieldBusFrontEnd::write(const hal::AnalogOutputs& out) {
  ++tx_seq_;
  bool ok = true;
  if (fd_) {
    ok = bus_.send(encode_demand_fd(ids_.amplifier, tx_seq_, out.amplifiers_enabled, out.spin_speed_command_hz,
                                    out.current_demand_a));
  } else {
    // Drive first: the demand frame is the one the amplifier node acts on (period sync).
    ok = bus_.send(encode_drive(ids_.amplifier, tx_seq_, out.amplifiers_enabled, out.spin_speed_command_hz));
    ok = bus_.send(encode_demand(ids_.amplifier, out.amplifiers_enabled ? out.current_demand_a
                                                                         : std::array<double, 4>{})) && ok;
  }
  if (!ok) bump(tx_failures_);
  const int64_t now = clock_.now_ns();
  if (now >= next_heartbeat_ns_) {
    next_heartbeat_ns_ = now + heartbeat_period_ns_;
    const uint8_t state = sup_ ? static_cast<uint8_t>(sup_->state()) : 0;
    if (!bus_.send(encode_heartbeat(ids_.board, nmt_operational, state))) bump(tx_failures_);
  }
}

FieldBusCounters FieldBusFrontEnd::counters() const {
  FieldBusCounters c;
  c.samples = samples_.load(std::memory_order_relaxed);
  c.stale_periods = stale_.load(std::memory_order_relaxed);
  c.malformed = malformed_.load(std::memory_order_relaxed);
  c.foreign = foreign_.load(std::memory_order_relaxed);
  c.error_frames = error_frames_.load(std::memory_order_relaxed);
  c.node_timeouts = timeouts_.load(std::memory_order_relaxed);
  c.amp_faults = amp_faults_.load(std::memory_order_relaxed);
  c.tx_failures = tx_failures_.load(std::memory_order_relaxed);
  return c;
}

}  // namespace amb::fieldbus
