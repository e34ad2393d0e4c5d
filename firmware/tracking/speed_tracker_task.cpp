#include "firmware/tracking/speed_tracker_task.hpp"

#include <cmath>

namespace amb::fw {

std::string SpeedTrackerTask::configure(const model::signal::SpeedTrackerOptions& options,
                                        size_t max_gap_samples) {
  if (std::string err = tracker_.configure(options); !err.empty()) return err;
  max_gap_samples_ = max_gap_samples;
  sample_period_ns_ = 1e9 / options.stft.sample_rate_hz;
  have_last_ = false;
  update_seq_ = 0;
  counters_ = {};
  published_.store(TrackedSpeed{});
  return {};
}

void SpeedTrackerTask::feed(double value) {
  ++counters_.samples;
  if (!tracker_.push(value)) return;
  const model::signal::SpeedEstimate& e = tracker_.latest();
  TrackedSpeed out;
  out.t_ns = first_t_ns_ + static_cast<int64_t>(std::llround(e.t_s * 1e9));
  out.speed_hz = e.speed_hz;
  out.confidence = e.confidence;
  out.update_seq = ++update_seq_;
  out.lost = e.lost ? 1 : 0;
  out.below_min = e.below_min ? 1 : 0;
  out.mode = static_cast<uint8_t>(tracker_.summary().mode);
  published_.store(out);
  ++counters_.updates;
}

size_t SpeedTrackerTask::poll(size_t max_samples) {
  size_t n = 0;
  TrackerSample s;
  while (n < max_samples && ring_.pop(s)) {
    ++n;
    if (have_last_ && s.seq != last_seq_ + 1) {
      const uint64_t missing = s.seq > last_seq_ ? s.seq - last_seq_ - 1 : 0;
      ++counters_.gaps;
      if (missing > max_gap_samples_ || s.seq <= last_seq_) {
        // The window would splice unrelated signal: start afresh (tracker reports lost).
        tracker_.reset();
        ++counters_.resets;
        have_last_ = false;
      } else {
        for (uint64_t i = 0; i < missing; ++i) feed(last_value_);
        counters_.gap_samples += missing;
      }
    }
    if (!have_last_) {
      first_t_ns_ = s.t_ns;
      have_last_ = true;
    }
    last_seq_ = s.seq;
    last_value_ = s.value;
    feed(s.value);
  }
  counters_.ring_drops = ring_.dropped();
  return n;
}

}  // namespace amb::fw
