#pragma once
// SocketCAN raw socket (classic CAN or CAN FD) as a hal::CanBus: non-blocking send/receive
// (MSG_DONTWAIT), kernel receive filters, error frames, bus-off handling and counted drops.
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "hal/interfaces.hpp"

namespace amb::hal::linux_hw {

/// One kernel receive filter: a frame passes if (frame_id & mask) == (id & mask).
struct CanFilter {
  uint32_t id = 0;        ///< identifier to match (11- or 29-bit)
  uint32_t mask = 0x7FF;  ///< bits of the identifier that must match
  bool extended = false;  ///< filter applies to 29-bit identifiers
};

struct SocketCanOptions {
  std::string interface = "can0";      ///< network interface, e.g. "can0", "vcan0"
  bool fd = false;                     ///< enable CAN FD frames (CAN_RAW_FD_FRAMES)
  std::vector<CanFilter> filters;      ///< empty: receive every data frame
  bool receive_own = false;            ///< also receive frames this socket sent (tests)
  int64_t bus_off_restart_ns = 100'000'000;  ///< after bus-off, hold sends this long before retrying, ns
  int rx_buffer_bytes = 0;             ///< SO_RCVBUF, bytes (0: kernel default)
};

class SocketCanBus final : public CanBus {
 public:
  SocketCanBus() = default;
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  /// Configure: open, bind to the interface, install filters and the error mask. Not RT.
  bool open(const SocketCanOptions& options, std::string& error);
  void close();
  bool is_open() const { return fd_ >= 0; }

  /// [RT] Non-blocking send; false and a counted drop when the queue is full, the interface
  /// is down, the controller is bus-off, or the frame does not fit the mode (FD frame on a
  /// classic socket).
  bool send(const CanFrame& frame) override;
  /// [RT] Non-blocking receive of one frame (data or error frame; error frames have
  /// `error` set, their class bits in `id` and the controller detail in `data`).
  bool receive(CanFrame& frame) override;
  /// Any thread: counters since open.
  CanStats stats() const override;
  /// Any thread: the bus-off hold is active.
  bool bus_off() const { return bus_off_.load(std::memory_order_relaxed); }
  /// The socket, for poll() in non-RT users (amb-plant).
  int fd() const { return fd_; }
  /// Count a frame the protocol layer refused (CanStats::malformed).
  void count_malformed() { malformed_.fetch_add(1, std::memory_order_relaxed); }

 private:
  int fd_ = -1;
  bool fd_mode_ = false;
  int64_t bus_off_restart_ns_ = 100'000'000;
  int64_t bus_off_since_ns_ = 0;
  uint32_t last_overflow_count_ = 0;
  std::atomic<bool> bus_off_{false};
  std::atomic<uint64_t> tx_frames_{0}, rx_frames_{0}, tx_dropped_{0}, rx_dropped_{0}, error_frames_{0},
      bus_off_events_{0}, malformed_{0};
};

}  // namespace amb::hal::linux_hw
