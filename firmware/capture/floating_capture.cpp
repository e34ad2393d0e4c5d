#include "firmware/capture/floating_capture.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "firmware/board/board.hpp"

namespace amb::fw {

FloatingCapture::FloatingCapture() = default;
FloatingCapture::~FloatingCapture() = default;

void FloatingCapture::configure(const CaptureParams& p, const std::array<double, 4>& sensor_angle_deg,
                                double rate_hz) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("capture: rate_hz must be > 0");
  if (p.event_buffers < 1 || p.event_buffers > k_max_buffers)
    throw std::invalid_argument("capture: event_buffers must be 1..8");
  p_ = p;
  const CaptureSizes sz = capture_sizes(p, rate_hz);
  pre_n_ = sz.pre_samples;
  post_n_ = sz.post_samples;
  // Enough pre-trigger copies per period to finish before the post window ends, which is
  // before the ring can overwrite the oldest pre-trigger sample (ring >= pre + post + 1).
  pre_per_sample_ = std::max<uint32_t>(1, (pre_n_ + post_n_ - 1) / post_n_);
  hold_n_ = std::max<uint32_t>(1, static_cast<uint32_t>(std::ceil(p.rearm_hold_s * rate_hz - 1e-9)));
  const uint64_t ring_n = sz.ring_samples;
  ring_.assign(ring_n, LoopSample{});
  ring_mask_ = ring_n - 1;
  events_.clear();
  events_.resize(static_cast<size_t>(p.event_buffers));
  for (auto& e : events_) e.samples.assign(static_cast<size_t>(pre_n_) + post_n_, LoopSample{});
  ready_ = std::make_unique<SpscRing<uint32_t, k_max_buffers>>();
  free_ = std::make_unique<SpscRing<uint32_t, k_max_buffers>>();
  for (uint32_t i = 0; i < static_cast<uint32_t>(p.event_buffers); ++i) free_->push(i);
  monitor_.configure(p.triggers, sensor_angle_deg, rate_hz);

  head_ = 0;
  have_last_seq_ = false;
  last_seq_ = 0;
  mode_ = Mode::armed;
  clear_n_ = 0;
  cur_ = 0;
  pre_src_ = 0;
  pre_count_ = pre_done_ = post_done_ = 0;
  window_gaps_ = 0;
  captures_ = 0;
  manual_request_.store(false);
  mode_pub_.store(static_cast<uint8_t>(mode_));
  for (auto* c : {&n_samples_, &n_triggers_, &n_frozen_, &n_lost_, &n_suppressed_, &n_gaps_}) c->store(0);
}

bool FloatingCapture::request_manual_trigger() {
  if (!p_.triggers.manual.enabled) return false;
  manual_request_.store(true, std::memory_order_release);
  return true;
}

void FloatingCapture::on_sample(const LoopSample& s) {
  if (ring_.empty()) return;  // not configured
  bump(n_samples_);
  const bool gap = have_last_seq_ && s.seq != last_seq_ + 1;
  if (gap) bump(n_gaps_);
  have_last_seq_ = true;
  last_seq_ = s.seq;

  ring_[head_ & ring_mask_] = s;
  ++head_;

  // Cheap check first: the exchange (a read-modify-write) only when a request is pending.
  const bool manual = manual_request_.load(std::memory_order_relaxed) &&
                      manual_request_.exchange(false, std::memory_order_acquire);
  const uint32_t rising = monitor_.update(s, manual);
  clear_n_ = monitor_.all_clear() ? std::min(clear_n_ + 1, hold_n_) : 0;

  switch (mode_) {
    case Mode::armed:
      if (rising) start(s, rising);
      break;
    case Mode::capturing: {
      if (rising) bump(n_suppressed_);
      if (gap) ++window_gaps_;
      FrozenEvent& e = events_[cur_];
      e.samples[pre_count_ + post_done_++] = s;
      const uint32_t n = std::min(pre_per_sample_, pre_count_ - pre_done_);
      for (uint32_t i = 0; i < n; ++i, ++pre_done_) e.samples[pre_done_] = ring_[(pre_src_ + pre_done_) & ring_mask_];
      if (post_done_ == post_n_) freeze();
      break;
    }
    case Mode::holdoff:
      if (rising) bump(n_suppressed_);
      if (clear_n_ >= hold_n_) mode_ = Mode::armed;
      break;
  }
  mode_pub_.store(static_cast<uint8_t>(mode_), std::memory_order_relaxed);
}

void FloatingCapture::start(const LoopSample& s, uint32_t causes) {
  uint32_t idx = 0;
  if (!free_->pop(idx)) {
    // No buffer: the consumer is behind. Lose this event rather than wait; stay disarmed
    // until the incident is over so it is not captured half-way through.
    bump(n_lost_);
    mode_ = Mode::holdoff;
    return;
  }
  bump(n_triggers_);
  cur_ = idx;
  FrozenEvent& e = events_[cur_];
  const uint64_t before = head_ - 1;  // samples in the ring before the trigger sample
  pre_count_ = static_cast<uint32_t>(std::min<uint64_t>(pre_n_, before));
  pre_src_ = before - pre_count_;
  pre_done_ = 0;
  post_done_ = 0;
  window_gaps_ = 0;
  FrozenEventHeader& h = e.header;
  h = FrozenEventHeader{};
  h.cause = primary_cause(causes);
  h.cause_mask = causes;
  h.cutoff_channels = monitor_.cutoff_channels();
  h.trigger_index = pre_count_;
  h.trigger_seq = s.seq;
  h.trigger_t_ns = s.t_ns;
  h.speed_at_trigger_hz = s.speed_hz;
  h.events_lost_before = n_lost_.load(std::memory_order_relaxed);
  mode_ = Mode::capturing;

  // The trigger sample is the first post-trigger sample.
  e.samples[pre_count_ + post_done_++] = s;
  const uint32_t n = std::min(pre_per_sample_, pre_count_);
  for (uint32_t i = 0; i < n; ++i, ++pre_done_) e.samples[pre_done_] = ring_[(pre_src_ + pre_done_) & ring_mask_];
  if (post_done_ == post_n_ && pre_done_ == pre_count_) freeze();
}

void FloatingCapture::freeze() {
  FrozenEvent& e = events_[cur_];
  // Any pre-trigger samples left (only if post_n_ is tiny): finish them now, bounded by pre_n_.
  for (; pre_done_ < pre_count_; ++pre_done_) e.samples[pre_done_] = ring_[(pre_src_ + pre_done_) & ring_mask_];
  FrozenEventHeader& h = e.header;
  h.sample_count = pre_count_ + post_n_;
  h.capture_number = ++captures_;
  h.first_t_ns = e.samples[0].t_ns;
  h.last_t_ns = e.samples[h.sample_count - 1].t_ns;
  // Gaps inside the pre-trigger part are found by the consumer from seq; count those seen
  // while recording the post-trigger part here.
  h.seq_gaps = window_gaps_;
  ready_->push(cur_);  // cannot fail: at most event_buffers indices are in flight
  bump(n_frozen_);
  mode_ = Mode::holdoff;
}

const FrozenEvent* FloatingCapture::take() {
  uint32_t idx = 0;
  if (!ready_ || !ready_->pop(idx)) return nullptr;
  return &events_[idx];
}

void FloatingCapture::release(const FrozenEvent* e) {
  if (!e) return;
  const auto idx = static_cast<uint32_t>(e - events_.data());
  free_->push(idx);
}

CaptureCounters FloatingCapture::counters() const {
  CaptureCounters c;
  c.samples = n_samples_.load(std::memory_order_relaxed);
  c.triggers = n_triggers_.load(std::memory_order_relaxed);
  c.events_frozen = n_frozen_.load(std::memory_order_relaxed);
  c.events_lost = n_lost_.load(std::memory_order_relaxed);
  c.triggers_suppressed = n_suppressed_.load(std::memory_order_relaxed);
  c.seq_gaps = n_gaps_.load(std::memory_order_relaxed);
  return c;
}

void configure_capture(FloatingCapture& c, const board::BoardConfig& b) {
  std::array<double, 4> angles{};
  for (size_t i = 0; i < 4; ++i) angles[i] = b.plant.sensor[i].angle_deg;
  c.configure(b.capture, angles, b.rate_hz);
}

}  // namespace amb::fw
