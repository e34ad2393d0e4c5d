#include "hal/linux/gpiod_discrete_io.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

namespace amb::hal::linux_hw {

GpiodDiscreteIo::GpiodDiscreteIo() : in_(new gpiod_line_bulk), out_(new gpiod_line_bulk) {
  gpiod_line_bulk_init(in_);
  gpiod_line_bulk_init(out_);
}

GpiodDiscreteIo::~GpiodDiscreteIo() {
  close();
  delete in_;
  delete out_;
}

void GpiodDiscreteIo::close() {
  if (chip_) {
    // Leave the amplifiers disabled when the process lets go of the lines.
    if (gpiod_line_bulk_num_lines(out_) == 3) {
      const int zero[3] = {0, 0, 0};
      gpiod_line_set_value_bulk(out_, zero);
    }
    gpiod_chip_close(chip_);  // releases every requested line
  }
  chip_ = nullptr;
  gpiod_line_bulk_init(in_);
  gpiod_line_bulk_init(out_);
}

bool GpiodDiscreteIo::open(const GpioLineMap& p, const std::string& consumer, std::string& error) {
  close();
  chip_ = gpiod_chip_open_lookup(p.chip.c_str());
  if (!chip_) {
    error = "cannot open GPIO chip '" + p.chip + "': " + std::strerror(errno);
    return false;
  }
  const unsigned n_lines = gpiod_chip_num_lines(chip_);
  unsigned out_offsets[3] = {p.amplifier_enable, p.watchdog, p.status};
  unsigned in_offsets[2] = {p.amplifier_fault, p.landing_request};
  for (unsigned o : out_offsets)
    if (o >= n_lines) {
      error = "GPIO chip '" + p.chip + "' has " + std::to_string(n_lines) + " lines; line " + std::to_string(o) +
              " does not exist";
      close();
      return false;
    }
  for (unsigned o : in_offsets)
    if (o >= n_lines) {
      error = "GPIO chip '" + p.chip + "' has " + std::to_string(n_lines) + " lines; line " + std::to_string(o) +
              " does not exist";
      close();
      return false;
    }
  if (gpiod_chip_get_lines(chip_, out_offsets, 3, out_) != 0 ||
      gpiod_chip_get_lines(chip_, in_offsets, 2, in_) != 0) {
    error = "cannot get GPIO lines of '" + p.chip + "': " + std::strerror(errno);
    close();
    return false;
  }
  const int initial[3] = {0, 0, 0};
  if (gpiod_line_request_bulk_output(out_, consumer.c_str(), initial) != 0) {
    error = "cannot request GPIO output lines (enable, watchdog, status) of '" + p.chip + "': " + std::strerror(errno);
    close();
    return false;
  }
  if (gpiod_line_request_bulk_input(in_, consumer.c_str()) != 0) {
    error = "cannot request GPIO input lines (fault, landing) of '" + p.chip + "': " + std::strerror(errno);
    close();
    return false;
  }
  return true;
}

DiscreteInputs GpiodDiscreteIo::read() {
  DiscreteInputs d;
  if (!chip_) return d;
  int v[2] = {0, 0};
  if (gpiod_line_get_value_bulk(in_, v) != 0) {
    io_errors_.fetch_add(1, std::memory_order_relaxed);
    d.amplifier_fault = true;  // cannot see the fault line: assume the worst
    return d;
  }
  d.amplifier_fault = v[0] != 0;
  d.landing_request = v[1] != 0;
  return d;
}

void GpiodDiscreteIo::write(const DiscreteOutputs& out) {
  if (!chip_) return;
  const int v[3] = {out.amplifier_enable ? 1 : 0, out.watchdog ? 1 : 0, out.status_ok ? 1 : 0};
  if (gpiod_line_set_value_bulk(out_, v) != 0) io_errors_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace amb::hal::linux_hw
