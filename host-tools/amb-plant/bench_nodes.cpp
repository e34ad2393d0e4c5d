#include "host-tools/amb-plant/bench_nodes.hpp"

#include <algorithm>
#include <cmath>

namespace amb::plant {

namespace fb = amb::fieldbus;

BenchNodes::BenchNodes(model::Plant& plant, const board::BoardConfig& board, hal::CanBus& bus)
    : plant_(plant),
      bus_(bus),
      ids_{board.comms.can.board_node_id, board.comms.can.sensor_node_id, board.comms.can.amplifier_node_id},
      fd_(board.comms.can.fd),
      period_s_(1.0 / board.rate_hz),
      heartbeat_ns_(static_cast<int64_t>(board.comms.can.heartbeat_period_ms) * 1'000'000),
      timeout_ns_(static_cast<int64_t>(board.comms.can.node_timeout_ms) * 1'000'000 * 4),
      delay_whole_(static_cast<int>(std::floor(board.loop_delay_periods + 1e-12))),
      delay_frac_(std::max(0.0, board.loop_delay_periods - std::floor(board.loop_delay_periods + 1e-12))) {
  if (delay_frac_ < 1e-12) delay_frac_ = 0.0;
}

int64_t BenchCounters::round_trip_quantile_ns(double q) const {
  const double target = q * static_cast<double>(round_trips);
  double acc = 0.0;
  for (int i = 0; i < fw::LoopStats::k_bins; ++i) {
    acc += static_cast<double>(round_trip_hist[static_cast<size_t>(i)]);
    if (acc >= target) return std::min(fw::LoopStats::bin_upper_ns(i), max_round_trip_ns);
  }
  return max_round_trip_ns;
}

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
      if (sample_sent_ns_ >= 0) {
        const int64_t rt = std::max<int64_t>(0, now_ns - sample_sent_ns_);
        ++c_.round_trips;
        c_.max_round_trip_ns = std::max(c_.max_round_trip_ns, rt);
        ++c_.round_trip_hist[static_cast<size_t>(fw::LoopStats::bin_of(rt))];
      }
      in_.current_demand_a = m.current_a;
      const uint64_t k = c_.demands++;
      history_[k % k_history] = in_;
      // One board period of plant time per demand: the demand frame is the period clock. With
      // the loop delay the period is driven by the demands q and q + 1 frames back.
      auto back = [&](uint64_t n) { return n <= k ? history_[(k - n) % k_history] : model::PlantInputs{}; };
      const auto q = static_cast<uint64_t>(delay_whole_);
      if (delay_frac_ > 0.0) {
        plant_.step(delay_frac_ * period_s_, back(q + 1));
        plant_.step((1.0 - delay_frac_) * period_s_, back(q));
      } else {
        plant_.step(period_s_, back(q));
      }
      const model::PlantOutputs o = plant_.outputs();
      sample_sent_ns_ = now_ns;
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
