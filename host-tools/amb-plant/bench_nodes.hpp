#pragma once
// The HIL bench's sensor and amplifier nodes, emulated around a plant model: they speak the
// field-bus protocol (firmware/fieldbus/protocol.hpp, docs/fieldbus.md) on a hal::CanBus.
// Period-locked: each demand frame from the board advances the plant by one board period
// (1 / controller.rate_hz) and is answered with the new sample (position + current frames,
// or one FD sample frame). Heartbeats and amplifier status go out every heartbeat period.
#include <cstdint>

#include "firmware/board/board.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "hal/interfaces.hpp"
#include "model/plant/plant.hpp"

namespace amb::plant {

struct BenchCounters {
  uint64_t demands = 0;        ///< demand frames acted on (= plant periods stepped)
  uint64_t drives = 0;         ///< drive frames
  uint64_t board_heartbeats = 0;
  uint64_t malformed = 0;      ///< frames of ours refused by the codec
  uint64_t foreign = 0;        ///< other traffic
  uint64_t board_timeouts = 0; ///< board silent longer than the node timeout (amplifiers cut)
  uint64_t tx_failures = 0;
};

class BenchNodes {
 public:
  /// `plant`, `bus` must outlive this. Node ids, FD mode and timeouts come from board.comms.can.
  BenchNodes(model::Plant& plant, const board::BoardConfig& board, hal::CanBus& bus);
  /// Handle one received frame at time `now_ns` (any monotonic clock, ns).
  void on_frame(const hal::CanFrame& f, int64_t now_ns);
  /// Periodic duties at time `now_ns`: heartbeats, amplifier status, board-silence check.
  void tick(int64_t now_ns);
  const BenchCounters& counters() const { return c_; }
  const model::PlantInputs& inputs() const { return in_; }

 private:
  void send(const hal::CanFrame& f);
  model::Plant& plant_;
  hal::CanBus& bus_;
  fieldbus::NodeIds ids_;
  bool fd_;
  double period_s_;
  int64_t heartbeat_ns_, timeout_ns_;
  int64_t next_heartbeat_ns_ = 0, last_board_ns_ = -1;
  bool board_lost_ = false;
  uint16_t seq_ = 0;
  model::PlantInputs in_{};
  BenchCounters c_{};
};

}  // namespace amb::plant
