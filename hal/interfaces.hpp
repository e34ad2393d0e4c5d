#pragma once
// The hardware abstraction. Firmware links only against these interfaces; `linux`, `sim`
// and `replay` are sibling backends. Methods marked [RT] are called from the loop thread and
// must not allocate, lock, throw or make blocking system calls beyond what is stated.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hal/types.hpp"

namespace amb::hal {

/// Monotonic time source of the loop. Simulation and replay step it; Linux reads CLOCK_MONOTONIC.
class Clock {
 public:
  virtual ~Clock() = default;
  /// [RT] Current time, ns since an arbitrary epoch fixed at configure.
  virtual int64_t now_ns() = 0;
  /// [RT] Block until the absolute time `deadline_ns` (Linux: clock_nanosleep TIMER_ABSTIME;
  /// sim: advances the plant to the deadline). Returns the time actually reached, ns.
  virtual int64_t wait_until_ns(int64_t deadline_ns) = 0;
};

/// Displacement and coil-current samples in, current demands out.
class AnalogFrontEnd {
 public:
  virtual ~AnalogFrontEnd() = default;
  /// [RT] Fill `in` with the newest sample. Returns false if no valid sample arrived this period.
  virtual bool read(AnalogInputs& in) = 0;
  /// [RT] Send the demands of this period to the amplifiers.
  virtual void write(const AnalogOutputs& out) = 0;
};

/// Discrete lines: amplifier enable, fault inputs, watchdog, status.
class DiscreteIo {
 public:
  virtual ~DiscreteIo() = default;
  /// [RT] Read all inputs at once.
  virtual DiscreteInputs read() = 0;
  /// [RT] Write all outputs at once.
  virtual void write(const DiscreteOutputs& out) = 0;
};

/// Field bus to the sensor and amplifier nodes. Non-blocking in both directions.
class CanBus {
 public:
  virtual ~CanBus() = default;
  /// [RT] Queue a frame; false (and a counted drop) if it cannot be sent now.
  virtual bool send(const CanFrame& frame) = 0;
  /// [RT] Take one received frame if any; false when none is waiting.
  virtual bool receive(CanFrame& frame) = 0;
  /// Counters since configure.
  virtual CanStats stats() const = 0;
};

/// Modbus-style register access the firmware exposes; implemented by the firmware, served
/// by a SupervisoryServer backend in its own (non-real-time) thread.
class RegisterHandler {
 public:
  virtual ~RegisterHandler() = default;
  /// Modbus exception codes (0: success).
  enum Status : uint8_t { ok = 0, illegal_function = 1, illegal_address = 2, illegal_value = 3,
                          device_failure = 4, busy = 6 };
  /// Read `out.size()` holding/input registers starting at `address`.
  virtual Status read_registers(uint16_t address, std::span<uint16_t> out) = 0;
  /// Write `values` to holding registers starting at `address`.
  virtual Status write_registers(uint16_t address, std::span<const uint16_t> values) = 0;
};

/// The supervisory link server (Linux: libmodbus TCP). Runs outside the loop thread.
class SupervisoryServer {
 public:
  virtual ~SupervisoryServer() = default;
  /// Start serving `handler` (which must outlive the server). Returns false with `error` set.
  virtual bool start(RegisterHandler& handler, std::string& error) = 0;
  /// Stop serving and join the server thread.
  virtual void stop() = 0;
};

/// Persistent storage for events and the wear record. Not real-time.
class Storage {
 public:
  virtual ~Storage() = default;
  /// Replace `name` atomically with `bytes`: after a power loss at any instant, `name` holds
  /// either the old or the new content. Returns false with `error` set.
  virtual bool write_atomic(std::string_view name, std::span<const uint8_t> bytes,
                            std::string& error) = 0;
  /// Read the whole of `name`. Returns false with `error` set if absent or unreadable.
  virtual bool read(std::string_view name, std::vector<uint8_t>& bytes, std::string& error) = 0;
  /// Names of the stored items, sorted.
  virtual std::vector<std::string> list() = 0;
  /// Remove `name`; true if it existed.
  virtual bool remove(std::string_view name) = 0;
  /// Bytes still available for new items.
  virtual uint64_t free_bytes() = 0;
};

/// Scheduling of the board's ordinary (non-real-time) threads: each such thread applies it to
/// itself once, when it starts (never from the loop; the loop's own real-time set-up is the
/// backend's, e.g. hal/linux/rt_thread.hpp). Linux sets nice values; a backend with nothing to
/// schedule (sim, replay) passes no ThreadScheduling at all.
class ThreadScheduling {
 public:
  virtual ~ThreadScheduling() = default;
  /// Put the calling thread below the board's other ordinary threads (background work that
  /// may only take what they leave). Returns false, changing nothing, when refused (not fatal).
  virtual bool make_current_thread_background() = 0;
};

}  // namespace amb::hal
