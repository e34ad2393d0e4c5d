#include "hal/sim/sim_rig.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

namespace amb::hal::sim {

namespace {
int64_t wall_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

SimRig::SimRig(std::unique_ptr<model::Plant> plant, bool tach) : plant_(std::move(plant)), tach_(tach) {}

void SimRig::set_paced(bool paced) {
  paced_ = paced;
  wall_start_ns_ = wall_ns() - t_ns_;
}

void SimRig::set_demand_delay_ns(int64_t delay_ns) {
  if (delay_ns < 0) throw std::invalid_argument("sim: demand delay must be >= 0 ns, got " + std::to_string(delay_ns));
  demand_delay_ns_ = delay_ns;
}

void SimRig::submit(const model::PlantInputs& in) {
  if (demand_delay_ns_ == 0) {
    inputs_ = in;
    return;
  }
  if (pending_count_ == k_max_pending) {
    // More writes within the delay than the queue holds: the oldest acts now (counted).
    inputs_ = pending_[pending_head_].inputs;
    pending_head_ = (pending_head_ + 1) % k_max_pending;
    --pending_count_;
    ++delay_overflows_;
  }
  pending_[(pending_head_ + pending_count_) % k_max_pending] = {t_ns_ + demand_delay_ns_, in};
  ++pending_count_;
}

void SimRig::advance_to(int64_t deadline_ns) {
  // Each demand due by the deadline: the plant runs to its time on the demand before it.
  while (pending_count_ > 0 && pending_[pending_head_].act_ns <= deadline_ns) {
    const PendingDemand& p = pending_[pending_head_];
    if (p.act_ns > t_ns_) {
      plant_->step(static_cast<double>(p.act_ns - t_ns_) * 1e-9, inputs_);
      t_ns_ = p.act_ns;
    }
    inputs_ = p.inputs;
    pending_head_ = (pending_head_ + 1) % k_max_pending;
    --pending_count_;
  }
  if (deadline_ns > t_ns_) {
    plant_->step(static_cast<double>(deadline_ns - t_ns_) * 1e-9, inputs_);
    t_ns_ = deadline_ns;
  }
}

int64_t HostMonotonicClock::now_ns() { return wall_ns(); }

int64_t HostMonotonicClock::wait_until_ns(int64_t deadline_ns) {
  const int64_t now = wall_ns();
  if (deadline_ns > now) std::this_thread::sleep_for(std::chrono::nanoseconds(deadline_ns - now));
  return wall_ns();
}

int64_t SimClock::now_ns() { return rig_.t_ns_; }

int64_t SimClock::wait_until_ns(int64_t deadline_ns) {
  rig_.advance_to(deadline_ns);
  if (rig_.paced_) {
    const int64_t wake = rig_.wall_start_ns_ + deadline_ns;
    const int64_t now = wall_ns();
    if (wake > now) std::this_thread::sleep_for(std::chrono::nanoseconds(wake - now));
  }
  return rig_.t_ns_;
}

bool SimAnalogFrontEnd::read(AnalogInputs& in) {
  if (rig_.read_failures_left_ > 0) {
    --rig_.read_failures_left_;
    return false;
  }
  const model::PlantOutputs o = rig_.plant_->outputs();
  in.t_ns = rig_.t_ns_;
  for (size_t i = 0; i < 4; ++i) {
    // Samples are delivered at the front end's resolution: float32, as the capture stores
    // them (an ADC word is exact in float32), so a replayed capture is bit-exact.
    in.displacement_m[i] = static_cast<float>(o.displacement_m[i]);
    in.coil_current_a[i] = static_cast<float>(o.coil_current_a[i]);
  }
  in.tach_speed_hz = rig_.tach_ ? static_cast<float>(o.spin_speed_hz) : -1.0;
  in.fault_bits = 0;
  return true;
}

void SimAnalogFrontEnd::write(const AnalogOutputs& out) {
  model::PlantInputs in;
  for (size_t i = 0; i < 4; ++i) in.current_demand_a[i] = out.current_demand_a[i];
  in.amplifiers_enabled = out.amplifiers_enabled;
  in.spin_speed_command_hz = out.spin_speed_command_hz;
  rig_.submit(in);
}

bool MemoryStorage::write_atomic(std::string_view name, std::span<const uint8_t> bytes, std::string& error) {
  uint64_t used = 0;
  for (const auto& [k, v] : items_)
    if (k != name) used += v.size();
  if (used + bytes.size() > capacity_) {
    error = "storage full: " + std::to_string(bytes.size()) + " bytes needed, " +
            std::to_string(capacity_ - used) + " free";
    return false;
  }
  items_[std::string(name)] = std::vector<uint8_t>(bytes.begin(), bytes.end());
  return true;
}

bool MemoryStorage::read(std::string_view name, std::vector<uint8_t>& bytes, std::string& error) {
  auto it = items_.find(name);
  if (it == items_.end()) {
    error = "no such item: " + std::string(name);
    return false;
  }
  bytes = it->second;
  return true;
}

std::vector<std::string> MemoryStorage::list() {
  std::vector<std::string> names;
  for (const auto& [k, v] : items_) names.push_back(k);
  return names;
}

bool MemoryStorage::remove(std::string_view name) {
  auto it = items_.find(name);
  if (it == items_.end()) return false;
  items_.erase(it);
  return true;
}

uint64_t MemoryStorage::free_bytes() {
  uint64_t used = 0;
  for (const auto& [k, v] : items_) used += v.size();
  return capacity_ - used;
}

bool LoopbackCanBus::send(const CanFrame& frame) {
  if (!peer_ || peer_->head_ - peer_->tail_ >= k_capacity) {
    ++stats_.tx_dropped;
    return false;
  }
  peer_->queue_[peer_->head_++ % k_capacity] = frame;
  ++stats_.tx_frames;
  return true;
}

bool LoopbackCanBus::receive(CanFrame& frame) {
  if (tail_ == head_) return false;
  frame = queue_[tail_++ % k_capacity];
  ++stats_.rx_frames;
  return true;
}

}  // namespace amb::hal::sim
