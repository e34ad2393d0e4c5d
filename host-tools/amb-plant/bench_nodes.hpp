#pragma once
// The HIL bench's sensor and amplifier nodes, emulated around a plant model: they speak the
// field-bus protocol (firmware/fieldbus/protocol.hpp, docs/fieldbus.md) on a hal::CanBus.
// Period-locked: each demand frame from the board advances the plant by one board period
// (1 / controller.rate_hz) and is answered with the new sample (position + current frames,
// or one FD sample frame). Heartbeats and amplifier status go out every heartbeat period.
//
// Loop delay (board key controller.loop_delay_periods = q + f, q whole periods): the demand of a
// frame acts on the plant f periods into the period q periods after it; over a period the plant
// runs f T on the demand before and (1 - f) T on it (as the sim backend, exact for the hold).
// The board's round trip, sample frame sent -> demand frame received, is measured (wall time)
// into a histogram with LoopStats' bins.
#include <array>
#include <cstdint>

#include "firmware/app/loop_runner.hpp"
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
  /// Sample frame sent -> next demand frame received, ns (the board's loop as seen from here:
  /// its wake-up, read, step and write, plus both frames on the bus).
  uint64_t round_trips = 0;
  int64_t max_round_trip_ns = 0;
  std::array<uint64_t, fw::LoopStats::k_bins> round_trip_hist{};
  /// Round trip below which fraction `q` of them fell, ns (upper bin edge, at most the max).
  int64_t round_trip_quantile_ns(double q) const;
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
  // Demands of the last periods (ring, by demand count) and the delay split.
  static constexpr size_t k_history = 4;
  std::array<model::PlantInputs, k_history> history_{};
  int delay_whole_ = 0;
  double delay_frac_ = 0.0;
  int64_t sample_sent_ns_ = -1;
  BenchCounters c_{};
};

}  // namespace amb::plant
