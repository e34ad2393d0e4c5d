#include "host-tools/amb-plant/bench_nodes.hpp"

namespace amb::plant {

namespace fb = amb::fieldbus;

BenchNodes::BenchNodes(model::Plant& plant, const board::BoardConfig& board, hal::CanBus& bus)
    : plant_(plant),
      bus_(bus),
      ids_{board.comms.can.board_node_id, board.comms.can.sensor_node_id, board.comms.can.amplifier_node_id},
      fd_(board.comms.can.fd),
      period_s_(1.0 / board.rate_hz),
      heartbeat_ns_(static_cast<int64_t>(board.comms.can.heartbeat_period_ms) * 1'000'000),
      timeout_ns_(static_cast<int64_t>(board.comms.can.node_timeout_ms) * 1'000'000 * 4) {}

void BenchNodes::send(const hal::CanFrame& f) {
  if (!bus_.send(f)) ++c_.tx_failures;
}

void BenchNodes::on_frame(const hal::CanFrame& f, int64_t now_ns) {
  if (f.error) return;
  fb::Message m;
  switch (fb::decode(f, ids_, fb::Side::nodes, m)) {
    case fb::DecodeResult::malformed: ++c_.malformed; return;
    case fb::DecodeResult::foreign: ++c_.foreign; return;
    case fb::DecodeResult::ok: break;
  }
  last_board_ns_ = now_ns;
  board_lost_ = false;
  switch (m.kind) {
    case fb::Kind::heartbeat: ++c_.board_heartbeats; return;
    case fb::Kind::drive:
      ++c_.drives;
      in_.amplifiers_enabled = (m.flags & fb::drive_amplifiers_enabled) != 0;
      in_.spin_speed_command_hz = m.speed_hz;
      return;
    case fb::Kind::demand_fd:
      in_.amplifiers_enabled = (m.flags & fb::drive_amplifiers_enabled) != 0;
      in_.spin_speed_command_hz = m.speed_hz;
      [[fallthrough]];
    case fb::Kind::demand: {
      ++c_.demands;
      in_.current_demand_a = m.current_a;
      // One board period of plant time per demand: the demand frame is the period clock.
      plant_.step(period_s_, in_);
      const model::PlantOutputs o = plant_.outputs();
      ++seq_;
      if (fd_) {
        send(fb::encode_sample_fd(ids_.sensor, seq_, o.displacement_m, o.coil_current_a, o.spin_speed_hz, 0));
      } else {
        send(fb::encode_position(ids_.sensor, o.displacement_m, 0));
        send(fb::encode_current(ids_.amplifier, o.coil_current_a, 0));
      }
      return;
    }
    default:
      return;
  }
}

void BenchNodes::tick(int64_t now_ns) {
  if (last_board_ns_ >= 0 && !board_lost_ && now_ns - last_board_ns_ > timeout_ns_) {
    // The board went silent: an amplifier node cuts its power stages on its own.
    board_lost_ = true;
    ++c_.board_timeouts;
    in_.amplifiers_enabled = false;
    in_.spin_speed_command_hz = 0.0;
  }
  if (now_ns < next_heartbeat_ns_) return;
  next_heartbeat_ns_ = now_ns + heartbeat_ns_;
  send(fb::encode_heartbeat(ids_.sensor, fb::nmt_operational, 0));
  send(fb::encode_heartbeat(ids_.amplifier, fb::nmt_operational, 0));
  send(fb::encode_amp_status(ids_.amplifier, ++seq_, in_.amplifiers_enabled ? fb::amp_enabled : 0, 48.0, 35.0, 0));
}

}  // namespace amb::plant
