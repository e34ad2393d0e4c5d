#include "firmware/sweep/sweep_generator.hpp"

#include <cmath>

namespace amb::fw {

const char* to_string(SweepState s) {
  switch (s) {
    case SweepState::idle: return "idle";
    case SweepState::settling: return "settling";
    case SweepState::recording: return "recording";
    case SweepState::storing: return "storing";
  }
  return "?";
}

const char* to_string(SweepAbort a) {
  switch (a) {
    case SweepAbort::none: return "none";
    case SweepAbort::orbit_limit: return "orbit_limit";
    case SweepAbort::operator_abort: return "operator_abort";
    case SweepAbort::left_levitation: return "left_levitation";
    case SweepAbort::fault: return "fault";
  }
  return "?";
}

const char* to_string(SweepRefusal r) {
  switch (r) {
    case SweepRefusal::none: return "none";
    case SweepRefusal::not_levitated: return "not_levitated";
    case SweepRefusal::fault: return "fault";
    case SweepRefusal::not_armed: return "not_armed";
    case SweepRefusal::amplitude_limit: return "amplitude_limit";
    case SweepRefusal::not_configured: return "not_configured";
    case SweepRefusal::busy: return "busy";
  }
  return "?";
}

std::string SweepGenerator::configure(const SweepParams& p, double rate_hz, double bias_current_a, double abort_orbit_m) {
  p_ = p;
  design_ = {};
  buffer_.clear();
  n_axes_ = 0;
  for (uint8_t a = 0; a < 4; ++a)
    if (p.axes[a]) order_[n_axes_++] = a;
  amplitude_a_ = p.amplitude_fraction * bias_current_a;
  abort_orbit_m_ = abort_orbit_m;
  config_refusal_ = SweepRefusal::not_configured;
  std::string err;
  if (!p.enabled) err = "[sweep] enabled = false";
  else if (n_axes_ == 0) err = "no axis to sweep";
  else if (p.recorded_periods == 0) err = "recorded_periods must be at least 1";
  else if (!(bias_current_a > 0.0)) err = "the bias current is not positive";
  else if (!(abort_orbit_m > 0.0)) err = "the abort orbit radius is not positive";
  else if (!(p.amplitude_fraction > 0.0)) err = "amplitude_fraction must be positive";
  else err = design_multisine(rate_hz, p.samples_per_period, p.f_min_hz, p.f_max_hz, p.lines, design_);
  if (err.empty() && p.amplitude_fraction > p.amplitude_limit_fraction) {
    err = "amplitude_fraction " + std::to_string(p.amplitude_fraction) + " exceeds the limit " +
          std::to_string(p.amplitude_limit_fraction);
    config_refusal_ = SweepRefusal::amplitude_limit;
  } else if (err.empty()) {
    config_refusal_ = SweepRefusal::none;
    buffer_.assign(static_cast<size_t>(n_axes_) * 4 * p.recorded_periods * p.samples_per_period, 0.0f);
  }
  reset();
  return err;
}

void SweepGenerator::reset() {
  state_ = SweepState::idle;
  k_ = period_ = 0;
  axis_i_ = axes_done_ = 0;
  aborted_ = false;
  abort_reason_ = SweepAbort::none;
  start_t_ns_ = end_t_ns_ = t_ns_ = 0;
  start_seq_ = seq_ = 0;
  speed_hz_ = 0.0;
  start_stamped_ = false;
  started_ = completed_ = aborts_ = 0;
  last_abort_ = SweepAbort::none;
  start_req_.store(false);
  abort_req_.store(false);
  ready_.store(false);
  released_.store(false);
  refusals_.store(0);
  last_refusal_.store(0);
  changed_ = false;
  published_.store(status());
}

void SweepGenerator::count_refusal(SweepRefusal r) {
  refusals_.fetch_add(1, std::memory_order_relaxed);
  last_refusal_.store(static_cast<uint8_t>(r), std::memory_order_relaxed);
}

void SweepGenerator::finish(SweepAbort reason) {
  aborted_ = reason != SweepAbort::none;
  abort_reason_ = reason;
  end_t_ns_ = t_ns_;
  if (aborted_) {
    ++aborts_;
    last_abort_ = reason;
  } else {
    ++completed_;
  }
  state_ = SweepState::storing;
  changed_ = true;
  ready_.store(true, std::memory_order_release);
}

double SweepGenerator::begin_step(const SweepInputs& in, int& axis) {
  axis = -1;
  t_ns_ = in.t_ns;
  seq_ = in.seq;
  // The flags are read first and exchanged only when set: a read-modify-write every period
  // would cost the loop a locked instruction each (amb-bench BM_ControlStep).
  auto take = [](std::atomic<bool>& f) {
    return f.load(std::memory_order_relaxed) && f.exchange(false, std::memory_order_acquire);
  };
  if (take(released_) && state_ == SweepState::storing) {
    state_ = SweepState::idle;
    changed_ = true;
  }
  const bool running = state_ == SweepState::settling || state_ == SweepState::recording;
  if (take(abort_req_) && running) {
    finish(SweepAbort::operator_abort);
    return 0.0;
  }
  if (take(start_req_)) {
    SweepRefusal r = config_refusal_;
    if (r == SweepRefusal::none) {
      if (state_ != SweepState::idle) r = SweepRefusal::busy;
      else if (in.fault) r = SweepRefusal::fault;
      else if (!in.levitated) r = SweepRefusal::not_levitated;
    }
    if (r != SweepRefusal::none) {
      count_refusal(r);
    } else {
      state_ = p_.settle_periods > 0 ? SweepState::settling : SweepState::recording;
      k_ = period_ = 0;
      axis_i_ = axes_done_ = 0;
      aborted_ = false;
      abort_reason_ = SweepAbort::none;
      start_stamped_ = false;
      speed_hz_ = in.speed_hz;
      ++started_;
      changed_ = true;
    }
  }
  if (state_ != SweepState::settling && state_ != SweepState::recording) return 0.0;
  if (in.fault) {
    finish(SweepAbort::fault);
    return 0.0;
  }
  if (!in.levitated) {
    finish(SweepAbort::left_levitation);
    return 0.0;
  }
  if (in.orbit_max_m > abort_orbit_m_) {
    finish(SweepAbort::orbit_limit);
    return 0.0;
  }
  axis = order_[axis_i_];
  return amplitude_a_ * static_cast<double>(design_.table[k_]);
}

void SweepGenerator::end_step(double uc_a, double u_a, double y_m) {
  if (state_ != SweepState::settling && state_ != SweepState::recording) return;
  const uint32_t n = p_.samples_per_period;
  if (period_ >= p_.settle_periods) {
    if (!start_stamped_) {
      start_stamped_ = true;
      start_t_ns_ = t_ns_;
      start_seq_ = seq_;
    }
    const size_t per_channel = static_cast<size_t>(p_.recorded_periods) * n;
    const size_t at = static_cast<size_t>(period_ - p_.settle_periods) * n + k_;
    float* base = buffer_.data() + static_cast<size_t>(axis_i_) * 4 * per_channel;
    base[at] = static_cast<float>(amplitude_a_ * static_cast<double>(design_.table[k_]));
    base[per_channel + at] = static_cast<float>(uc_a);
    base[2 * per_channel + at] = static_cast<float>(u_a);
    base[3 * per_channel + at] = static_cast<float>(y_m);
  }
  if (++k_ < n) return;
  k_ = 0;
  ++period_;
  changed_ = true;
  if (period_ == p_.settle_periods) state_ = SweepState::recording;
  if (period_ < p_.settle_periods + p_.recorded_periods) return;
  period_ = 0;
  ++axes_done_;
  if (++axis_i_ >= n_axes_) {
    axis_i_ = static_cast<uint8_t>(n_axes_ - 1);
    finish(SweepAbort::none);
    return;
  }
  state_ = p_.settle_periods > 0 ? SweepState::settling : SweepState::recording;
}

SweepStatus SweepGenerator::status() const {
  SweepStatus s;
  s.state = state_;
  const bool running = state_ == SweepState::settling || state_ == SweepState::recording;
  s.axis = running ? static_cast<int8_t>(order_[axis_i_]) : int8_t{-1};
  s.axis_index = axis_i_;
  s.axes_total = n_axes_;
  s.axes_done = axes_done_;
  s.period = period_;
  s.periods_per_axis = p_.settle_periods + p_.recorded_periods;
  s.started = started_;
  s.completed = completed_;
  s.aborts = aborts_;
  s.refusals = refusals_.load(std::memory_order_relaxed);
  s.last_abort = last_abort_;
  s.last_refusal = static_cast<SweepRefusal>(last_refusal_.load(std::memory_order_relaxed));
  return s;
}

SweepCaptureView SweepGenerator::view() const {
  SweepCaptureView v;
  v.samples_per_period = p_.samples_per_period;
  v.settle_periods = p_.settle_periods;
  v.recorded_periods = p_.recorded_periods;
  v.bins = design_.bins;
  v.amplitude_a = amplitude_a_;
  v.crest_factor = design_.crest_factor;
  v.axes = order_;
  v.axes_done = axes_done_;
  v.aborted = aborted_;
  v.abort_reason = abort_reason_;
  v.start_t_ns = start_t_ns_;
  v.start_seq = start_seq_;
  v.end_t_ns = end_t_ns_;
  v.speed_hz = speed_hz_;
  v.data = buffer_;
  return v;
}

}  // namespace amb::fw
