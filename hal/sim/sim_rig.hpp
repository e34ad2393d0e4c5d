#pragma once
// The `sim` HAL backend: a plant model stepped in lockstep with the loop clock. Waiting for a
// deadline advances the plant to it, holding the last demands (zero-order hold); reading
// samples the plant's sensors. Optionally paced to wall time.
//
// Loop delay: the step takes no simulated time, so a demand written after reading the sample of
// t_k would act from t_k on. With a demand delay D (the board's computation and transport
// delay) it acts from t_k + D: waiting for a deadline steps the plant to each pending demand's
// time with the demand before it held, applies it, and steps on. Each held piece is integrated
// as its own plant step, so a fractional delay is exact for the zero-order hold (no rounding to
// the plant's sub-step).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hal/interfaces.hpp"
#include "model/plant/plant.hpp"

namespace amb::hal::sim {

class SimRig;

class SimClock final : public Clock {
 public:
  explicit SimClock(SimRig& rig) : rig_(rig) {}
  int64_t now_ns() override;
  int64_t wait_until_ns(int64_t deadline_ns) override;

 private:
  SimRig& rig_;
};

/// The host's monotonic clock (std::chrono::steady_clock), for measuring the host's work in a
/// simulation (LoopRunner::set_stamp_clock). [RT] now_ns is a vDSO clock read.
class HostMonotonicClock final : public Clock {
 public:
  int64_t now_ns() override;
  int64_t wait_until_ns(int64_t deadline_ns) override;
};

class SimAnalogFrontEnd final : public AnalogFrontEnd {
 public:
  explicit SimAnalogFrontEnd(SimRig& rig) : rig_(rig) {}
  bool read(AnalogInputs& in) override;
  void write(const AnalogOutputs& out) override;

 private:
  SimRig& rig_;
};

class SimDiscreteIo final : public DiscreteIo {
 public:
  DiscreteInputs read() override { return inputs; }
  void write(const DiscreteOutputs& out) override { outputs = out; }
  DiscreteInputs inputs{};    ///< set by the scenario or test
  DiscreteOutputs outputs{};  ///< last written by the firmware
};

/// Owns the plant and the lockstep time; hands out the HAL objects.
class SimRig {
 public:
  /// `plant` is reset by the caller; `tach`: provide a tachometer reading to the firmware.
  explicit SimRig(std::unique_ptr<model::Plant> plant, bool tach = false);
  /// Pace the plant to wall time (real-time factor 1) instead of running as fast as possible.
  void set_paced(bool paced);
  /// Delay from a demand's write to its action on the plant, ns (configure time; 0: none, as
  /// before). Throws std::invalid_argument if negative. The queue holds k_max_pending demands:
  /// enough for 2 periods of delay with one write per period (more writes within the delay
  /// apply the oldest early and count it in delay_overflows()).
  void set_demand_delay_ns(int64_t delay_ns);
  int64_t demand_delay_ns() const { return demand_delay_ns_; }
  uint64_t delay_overflows() const { return delay_overflows_; }
  static constexpr size_t k_max_pending = 8;
  /// Make the next `n` reads fail (front-end dropout injection).
  void inject_read_failures(int n) { read_failures_left_ = n; }

  Clock& clock() { return clock_; }
  /// The host's monotonic clock (not the simulated one).
  Clock& wall_clock() { return wall_; }
  AnalogFrontEnd& analog() { return afe_; }
  SimDiscreteIo& discrete() { return dio_; }
  model::Plant& plant() { return *plant_; }
  int64_t time_ns() const { return t_ns_; }
  /// The demands acting on the plant now (after the delay).
  const model::PlantInputs& plant_inputs() const { return inputs_; }

 private:
  friend class SimClock;
  friend class SimAnalogFrontEnd;
  std::unique_ptr<model::Plant> plant_;
  bool tach_;
  bool paced_ = false;
  int64_t wall_start_ns_ = 0;
  int64_t t_ns_ = 0;
  int read_failures_left_ = 0;
  model::PlantInputs inputs_{};
  struct PendingDemand {
    int64_t act_ns = 0;           ///< time it starts acting, ns
    model::PlantInputs inputs{};
  };
  void submit(const model::PlantInputs& in);  // [RT]
  void advance_to(int64_t deadline_ns);       // [RT]
  int64_t demand_delay_ns_ = 0;
  std::array<PendingDemand, k_max_pending> pending_{};
  size_t pending_head_ = 0, pending_count_ = 0;
  uint64_t delay_overflows_ = 0;
  SimClock clock_{*this};
  HostMonotonicClock wall_{};
  SimAnalogFrontEnd afe_{*this};
  SimDiscreteIo dio_{};
};

/// Storage in memory with a capacity; write_atomic is all-or-nothing.
class MemoryStorage final : public Storage {
 public:
  explicit MemoryStorage(uint64_t capacity_bytes) : capacity_(capacity_bytes) {}
  bool write_atomic(std::string_view name, std::span<const uint8_t> bytes, std::string& error) override;
  bool read(std::string_view name, std::vector<uint8_t>& bytes, std::string& error) override;
  std::vector<std::string> list() override;
  bool remove(std::string_view name) override;
  uint64_t free_bytes() override;

 private:
  uint64_t capacity_;
  std::map<std::string, std::vector<uint8_t>, std::less<>> items_;
};

/// Two ends of an in-process CAN bus (for SIL of the field-bus protocol).
class LoopbackCanBus final : public CanBus {
 public:
  /// Connect two ends; frames sent on one are received on the other.
  static void connect(LoopbackCanBus& a, LoopbackCanBus& b) { a.peer_ = &b; b.peer_ = &a; }
  bool send(const CanFrame& frame) override;
  bool receive(CanFrame& frame) override;
  CanStats stats() const override { return stats_; }

 private:
  static constexpr size_t k_capacity = 1024;
  LoopbackCanBus* peer_ = nullptr;
  std::array<CanFrame, k_capacity> queue_{};
  size_t head_ = 0, tail_ = 0;
  CanStats stats_{};
};

}  // namespace amb::hal::sim
