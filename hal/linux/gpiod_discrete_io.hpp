#pragma once
// Discrete lines on a GPIO chip through the libgpiod v1.6 C API. Lines are requested once at
// open (configure); read() and write() are one bulk ioctl each (gpiod_line_get_value_bulk /
// gpiod_line_set_value_bulk), with no allocation per call.
#include <atomic>
#include <cstdint>
#include <string>

#include "hal/interfaces.hpp"

struct gpiod_chip;
struct gpiod_line_bulk;

namespace amb::hal::linux_hw {

/// Which chip and line offsets carry the discrete signals (all lines active high).
struct GpioLineMap {
  std::string chip = "gpiochip0";   ///< chip name, path (/dev/gpiochipN), label or number
  unsigned amplifier_enable = 0;    ///< output line offset
  unsigned watchdog = 3;            ///< output line offset
  unsigned status = 4;              ///< output line offset
  unsigned amplifier_fault = 1;     ///< input line offset
  unsigned landing_request = 2;     ///< input line offset
};

class GpiodDiscreteIo final : public DiscreteIo {
 public:
  GpiodDiscreteIo();
  ~GpiodDiscreteIo() override;
  GpiodDiscreteIo(const GpiodDiscreteIo&) = delete;
  GpiodDiscreteIo& operator=(const GpiodDiscreteIo&) = delete;

  /// Open the chip (name, path, label or number) and request the lines of `p`: outputs
  /// amplifier enable (initially low), watchdog, status; inputs amplifier fault, landing request.
  bool open(const GpioLineMap& p, const std::string& consumer, std::string& error);
  void close();

  /// [RT] One bulk read of the two inputs. A failed read counts and returns a fault (safe side).
  DiscreteInputs read() override;
  /// [RT] One bulk write of the three outputs.
  void write(const DiscreteOutputs& out) override;

  uint64_t io_errors() const { return io_errors_.load(std::memory_order_relaxed); }

 private:
  gpiod_chip* chip_ = nullptr;
  gpiod_line_bulk* in_ = nullptr;   // [amplifier fault, landing request]
  gpiod_line_bulk* out_ = nullptr;  // [amplifier enable, watchdog, status]
  std::atomic<uint64_t> io_errors_{0};
};

}  // namespace amb::hal::linux_hw
