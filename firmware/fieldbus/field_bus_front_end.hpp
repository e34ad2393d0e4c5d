#pragma once
// The board side of the field bus as a hal::AnalogFrontEnd: samples come from the sensor and
// amplifier nodes over a hal::CanBus, demands go to the amplifier node. Works with any CanBus
// (SocketCAN on the board, LoopbackCanBus in SIL tests). read()/write() are [RT]: they drain
// and send a bounded number of frames, never block, allocate or throw.
//
// Safety: when a node has been silent for longer than `node_timeout_ms` while the rotor is
// levitated or running, the supervisor is sent to the safe state (FaultReason::comm_timeout).
// Malformed frames are counted and ignored.
#include <atomic>
#include <cstdint>

#include "firmware/app/supervisor.hpp"
#include "firmware/comms/comms_params.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "hal/interfaces.hpp"

namespace amb::fieldbus {

/// Counters of the protocol layer (never reset).
struct FieldBusCounters {
  uint64_t samples = 0;          ///< position (or FD sample) frames accepted
  uint64_t stale_periods = 0;    ///< periods without a new position sample
  uint64_t malformed = 0;        ///< frames of ours refused by decode()
  uint64_t foreign = 0;          ///< frames not for this side (should be 0 with kernel filters)
  uint64_t error_frames = 0;     ///< controller error frames seen
  uint64_t node_timeouts = 0;    ///< node-silence events (each one leads to the safe state if levitated)
  uint64_t amp_faults = 0;       ///< amplifier status frames reporting a fault
  uint64_t tx_failures = 0;      ///< frames the bus would not take
};

class FieldBusFrontEnd final : public hal::AnalogFrontEnd {
 public:
  /// `bus`, `clock` and (optional) `supervisor` must outlive this.
  FieldBusFrontEnd(hal::CanBus& bus, hal::Clock& clock, const comms::CanParams& params,
                   fw::Supervisor* supervisor);

  /// [RT] Drain received frames (at most 64 per call); newest sample wins. False when no new
  /// position sample arrived since the last call or a node timed out.
  bool read(hal::AnalogInputs& in) override;
  /// [RT] Send the demands (classic: drive + demand frames; FD: one frame) and, when due, the
  /// board heartbeat.
  void write(const hal::AnalogOutputs& out) override;

  /// Any thread.
  FieldBusCounters counters() const;
  /// Any thread: the amplifier node reports a fault (latched until it reports none).
  bool amplifier_fault() const { return amp_fault_.load(std::memory_order_relaxed); }
  /// Any thread: every node has been heard within the timeout.
  bool nodes_alive() const { return nodes_alive_.load(std::memory_order_relaxed); }

  /// Frames drained per read() at most.
  static constexpr int k_max_frames_per_read = 64;

 private:
  void bump(std::atomic<uint64_t>& c) { c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed); }

  hal::CanBus& bus_;
  hal::Clock& clock_;
  fw::Supervisor* sup_;
  NodeIds ids_;
  bool fd_;
  int64_t node_timeout_ns_;
  int64_t heartbeat_period_ns_;
  int64_t next_heartbeat_ns_ = 0;
  int64_t last_sensor_ns_ = -1, last_amp_ns_ = -1;
  bool timed_out_ = false;
  uint16_t tx_seq_ = 0;
  hal::AnalogInputs last_{};
  // Single writer (the loop thread); relaxed atomics so other threads may read them.
  std::atomic<uint64_t> samples_{0}, stale_{0}, malformed_{0}, foreign_{0}, error_frames_{0}, timeouts_{0},
      amp_faults_{0}, tx_failures_{0};
  std::atomic<bool> amp_fault_{false};
  std::atomic<bool> nodes_alive_{false};
};

}  // namespace amb::fieldbus
