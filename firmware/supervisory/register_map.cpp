#include "firmware/supervisory/register_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "firmware/persistence/crc32c.hpp"

namespace amb::fw {

namespace {

using regs::k_block_bytes;

struct Range {
  uint16_t start, end;
};
// Every readable block; an address outside all of them is answered with exception 2.
constexpr Range k_readable[] = {
    {regs::identity, regs::identity_end},       {regs::state, regs::state_end},
    {regs::faults, regs::faults_end},           {regs::speed_estimate_mhz, regs::speed_end},
    {regs::orbit_radius_nm, regs::orbit_end},   {regs::loop_periods, regs::loop_end},
    {regs::can_stats, regs::stats_end},         {regs::command, regs::command + 1},
    {regs::event_count, regs::event_entry_end}, {regs::dl_select, regs::dl_select + 5},
    {regs::dl_status, regs::dl_end},            {regs::wear_present, regs::wear_end},
    {regs::wb_control, regs::wb_status_end},    {regs::analysis, regs::analysis_end},
    {regs::access_stats, regs::access_end},     {regs::storage_stats, regs::storage_end},
    {regs::arm, regs::arm_end},                 {regs::budget, regs::budget_end},
    {regs::buffers, regs::buffers_end},         {regs::sweep, regs::sweep_end},
};

void put16(std::vector<uint16_t>& b, size_t at, uint16_t v) { b[at] = v; }
void put32(std::vector<uint16_t>& b, size_t at, uint64_t v) {
  const auto u = static_cast<uint32_t>(std::min<uint64_t>(v, 0xFFFFFFFFu));
  b[at] = static_cast<uint16_t>(u >> 16);
  b[at + 1] = static_cast<uint16_t>(u);
}
void put_i32(std::vector<uint16_t>& b, size_t at, double v) {
  const double c = std::clamp(std::isfinite(v) ? std::round(v) : 0.0, -2147483647.0, 2147483647.0);
  const auto u = static_cast<uint32_t>(static_cast<int32_t>(c));
  b[at] = static_cast<uint16_t>(u >> 16);
  b[at + 1] = static_cast<uint16_t>(u);
}
void put64(std::vector<uint16_t>& b, size_t at, uint64_t v) {
  for (size_t i = 0; i < 4; ++i) b[at + i] = static_cast<uint16_t>(v >> (48 - 16 * i));
}
void put_string(std::vector<uint16_t>& b, size_t at, const std::string& s, size_t regs_count) {
  for (size_t i = 0; i < regs_count; ++i) {
    const uint8_t hi = 2 * i < s.size() ? static_cast<uint8_t>(s[2 * i]) : 0;
    const uint8_t lo = 2 * i + 1 < s.size() ? static_cast<uint8_t>(s[2 * i + 1]) : 0;
    b[at + i] = static_cast<uint16_t>(hi << 8 | lo);
  }
}
// A speed register: mHz, or k_speed_invalid when the value is not a valid speed.
void put_speed(std::vector<uint16_t>& b, size_t at, double hz, bool valid) {
  if (!valid || !std::isfinite(hz)) {
    const auto u = static_cast<uint32_t>(regs::k_speed_invalid);
    b[at] = static_cast<uint16_t>(u >> 16);
    b[at + 1] = static_cast<uint16_t>(u);
    return;
  }
  put_i32(b, at, hz * 1e3);
}
uint16_t pct(double x) { return static_cast<uint16_t>(std::lround(std::clamp(std::isfinite(x) ? x : 0.0, 0.0, 1.0) * 100.0)); }

uint32_t get32(std::span<const uint16_t> v, size_t at) { return static_cast<uint32_t>(v[at]) << 16 | v[at + 1]; }

}  // namespace

RegisterMap::RegisterMap(RegisterSources sources) : src_(std::move(sources)) {
  wb_staging_.resize(wear_record_size());
}

bool RegisterMap::unsafe_now() const {
  if (!src_.supervisor) return false;
  const State s = src_.supervisor->status().state;
  return s == State::levitating || s == State::running;
}

int64_t RegisterMap::now_ns() const {
  if (src_.now_ns) return src_.now_ns();
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

bool RegisterMap::take_arm(uint16_t op) {
  const bool armed = src_.arm_key != 0 && armed_op_ != regs::op_none && armed_op_ == op &&
                     now_ns() - armed_at_ns_ <= src_.arm_window_ns;
  // Single use: the write of the armed operation consumes the arm, accepted or not. A write of
  // another operation is refused and leaves the arm alone, so that a stray client cannot
  // cancel an operator's arm (nor use it: it names its operation).
  if (armed_op_ == op) armed_op_ = regs::op_none;
  if (!armed) ++access_.refused_not_armed;
  return armed;
}

// Which lifecycle states each command applies in (the same rules the supervisor applies when
// it takes the command; checked here too so that a refusal is an answer, not a silent no-op).
bool RegisterMap::state_allows(uint16_t op) const {
  const fw::Status st = src_.supervisor ? src_.supervisor->status() : fw::Status{};
  const bool resting = st.state != State::levitating && st.state != State::running;
  switch (op) {
    case regs::op_levitate: return st.state == State::inactive;
    case regs::op_run: return st.state == State::levitating && st.phase == Phase::levitated;
    case regs::op_land:
      return st.state == State::running || (st.state == State::levitating && st.phase != Phase::lowering);
    case regs::op_reset_fault: return st.state == State::fault;
    case regs::op_emergency_stop: return !resting;
    case regs::op_capture: return st.state != State::unconfigured;
    case regs::op_event_delete:
    case regs::op_wear_commit: return resting;
    default: return false;
  }
}

hal::RegisterHandler::Status RegisterMap::refuse_value() {
  ++access_.refused_value;
  return illegal_value;
}

void RegisterMap::refresh_events() {
  if (!src_.events) return;
  auto names = src_.events->list();
  if (names == event_names_) return;
  std::vector<EventEntry> fresh;
  for (const auto& n : names) {
    auto it = std::find_if(events_.begin(), events_.end(), [&](const EventEntry& e) { return e.name == n; });
    if (it != events_.end()) {
      fresh.push_back(*it);
      continue;
    }
    std::vector<uint8_t> bytes;
    std::string err;
    EventEntry e{n, 0, 0};
    if (src_.events->read(n, bytes, err)) {
      e.size = static_cast<uint32_t>(bytes.size());
      e.crc = crc32c(bytes);
    }
    fresh.push_back(std::move(e));
  }
  events_ = std::move(fresh);
  event_names_ = std::move(names);
  ++list_version_;
}

bool RegisterMap::render(uint16_t start, uint16_t end, Block& b) {
  b.assign(static_cast<size_t>(end - start), 0);
  const fw::Status st = src_.supervisor ? src_.supervisor->status() : fw::Status{};
  switch (start) {
    case regs::identity:
      put16(b, regs::magic, regs::k_magic_value);
      put16(b, regs::map_version, regs::k_map_version);
      put16(b, regs::firmware_version, 0x0001);
      put16(b, regs::unit_id, src_.unit_id);
      put16(b, regs::loop_rate_hz, static_cast<uint16_t>(std::lround(src_.rate_hz)));
      put16(b, regs::wear_record_bytes, static_cast<uint16_t>(wear_record_size()));
      put16(b, regs::download_block_bytes, k_block_bytes);
      put16(b, regs::writeback_chunk_bytes, regs::k_chunk_bytes);
      put_string(b, regs::board_name, src_.board_name, 16);
      return true;
    case regs::state: {
      put16(b, 0, static_cast<uint16_t>(st.state));
      put16(b, 1, static_cast<uint16_t>(st.phase));
      put16(b, 2, static_cast<uint16_t>(st.fault));
      uint16_t flags = 0;
      if (st.state == State::levitating || st.state == State::running) flags |= 1;
      if (st.state == State::fault) flags |= 2;
      if (src_.nodes_alive && src_.nodes_alive()) flags |= 4;
      put16(b, 3, flags);
      put64(b, 4, st.step);
      put32(b, 8, static_cast<uint64_t>(std::max<int64_t>(0, st.t_ns / 1'000'000)));
      return true;
    }
    case regs::faults:
      put32(b, 0, st.counters.read_failures);
      put32(b, 2, st.counters.sensor_fault_samples);
      put32(b, 4, st.counters.saturated_steps);
      put32(b, 6, st.counters.rejected_commands);
      put32(b, 8, st.counters.safe_state_entries);
      return true;
    case regs::speed_estimate_mhz: {
      const AnalysisStatus a = src_.analysis ? src_.analysis() : AnalysisStatus{};
      put_speed(b, 0, st.speed_estimate_hz, !st.speed_lost);
      put_i32(b, 2, st.speed_command_hz * 1e3);
      put16(b, 4, st.speed_lost ? 0 : pct(st.speed_confidence));
      uint16_t flags = static_cast<uint16_t>(src_.speed_source & 3u) << 3;
      if (st.speed_lost) flags |= 1;
      if (st.tracked.stale) flags |= 2;
      if (a.below_min) flags |= 4;
      if (a.defects_valid) flags |= 32;
      if (src_.analysis) flags |= 64;
      put16(b, 5, flags);
      put_speed(b, 6, st.tracked.speed_hz, !st.tracked.lost);
      put16(b, 8, pct(st.tracked.confidence));
      put16(b, 9, static_cast<uint16_t>(std::min(65535.0, st.tracked.age_s * 1e3)));
      put_speed(b, 10, st.tach_speed_hz, st.tach_speed_hz >= 0.0);
      put32(b, 12, st.counters.speed_disagreements);
      put32(b, 14, st.counters.speed_lost_periods);
      return true;
    }
    case regs::analysis: {
      const AnalysisStatus a = src_.analysis ? src_.analysis() : AnalysisStatus{};
      put32(b, 0, a.tracker_updates);
      put32(b, 2, a.samples);
      put32(b, 4, a.gaps);
      put32(b, 6, a.resets);
      put32(b, 8, a.ring_drops);
      const bool d = a.defects_valid != 0;
      put_speed(b, 10, a.ftf_hz, d);
      put_speed(b, 12, a.bpfo_hz, d);
      put_speed(b, 14, a.bpfi_hz, d);
      put_speed(b, 16, a.bsf_hz, d);
      return true;
    }
    case regs::budget: {
      const RuntimeBudget r = src_.runtime_budget ? src_.runtime_budget() : RuntimeBudget{};
      put32(b, 0, r.locked_kb);
      put32(b, 2, r.resident_kb);
      put32(b, 4, r.peak_resident_kb);
      auto share = [](double x) { return x < 0.0 ? uint16_t{0xFFFF} : static_cast<uint16_t>(std::min(65534.0, std::round(x * 1e4))); };
      put16(b, 6, share(r.loop_cpu_share));
      put16(b, 7, share(r.analysis_cpu_share));
      put16(b, 8, static_cast<uint16_t>(std::min(65535.0, std::round(r.window_s))));
      put32(b, 9, r.start_to_ready_ns < 0 ? 0xFFFFFFFFu : static_cast<uint64_t>(r.start_to_ready_ns / 1'000'000));
      const StorageBudget& sb = src_.storage_budget;
      put32(b, 11, sb.event_bytes_worst);
      put32(b, 13, sb.capacity_bytes / 1024);
      put16(b, 15, static_cast<uint16_t>(std::min<uint64_t>(sb.max_events, 0xFFFF)));
      put16(b, 16, static_cast<uint16_t>(std::min<uint64_t>(sb.events_kept, 0xFFFF)));
      return true;
    }
    case regs::buffers: {
      const size_t n = std::min<size_t>(src_.buffer_bytes.size(), regs::k_max_buffer_entries);
      put16(b, 0, static_cast<uint16_t>(n));
      for (size_t i = 0; i < n; ++i) put32(b, 1 + 2 * i, src_.buffer_bytes[i]);
      return true;
    }
    case regs::sweep: {
      const SweepStatus& w = st.sweep;
      put16(b, 0, static_cast<uint16_t>(w.state));
      put16(b, 1, w.axis < 0 ? uint16_t{0xFFFF} : static_cast<uint16_t>(w.axis));
      put16(b, 2, w.axis_index);
      put16(b, 3, w.axes_total);
      put16(b, 4, w.axes_done);
      put16(b, 5, static_cast<uint16_t>(std::min<uint32_t>(w.period, 0xFFFF)));
      put16(b, 6, static_cast<uint16_t>(std::min<uint32_t>(w.periods_per_axis, 0xFFFF)));
      put16(b, 7, static_cast<uint16_t>(w.last_abort));
      // Refusals: counted by the loop and by this link (atomics), read now, not at the last step.
      put16(b, 8, static_cast<uint16_t>(src_.supervisor ? src_.supervisor->sweep().last_refusal() : w.last_refusal));
      put32(b, 9, w.started);
      put32(b, 11, w.completed);
      put32(b, 13, w.aborts);
      put32(b, 15, src_.supervisor ? src_.supervisor->sweep().refusals() : w.refusals);
      const SweepStoreInfo si = src_.sweep_store ? src_.sweep_store() : SweepStoreInfo{};
      put32(b, 17, si.stored);
      put32(b, 19, si.last_number);
      if (src_.supervisor) {
        // Fixed after configure: read without the loop.
        const SweepGenerator& g = src_.supervisor->sweep();
        const SweepParams& p = g.params();
        put16(b, 21, static_cast<uint16_t>(g.config_refusal()));
        put32(b, 22, p.samples_per_period);
        put16(b, 24, static_cast<uint16_t>(std::min<uint32_t>(p.settle_periods, 0xFFFF)));
        put16(b, 25, static_cast<uint16_t>(std::min<uint32_t>(p.recorded_periods, 0xFFFF)));
        const auto& bins = g.design().bins;
        put16(b, 26, static_cast<uint16_t>(bins.size()));
        uint16_t mask = 0;
        for (size_t i = 0; i < 4; ++i) mask = static_cast<uint16_t>(mask | (p.axes[i] ? 1u << i : 0u));
        put16(b, 27, mask);
        const double df = src_.rate_hz / std::max<uint32_t>(1, p.samples_per_period);
        put32(b, 28, bins.empty() ? 0 : static_cast<uint64_t>(std::llround(bins.front() * df * 1e3)));
        put32(b, 30, bins.empty() ? 0 : static_cast<uint64_t>(std::llround(bins.back() * df * 1e3)));
        put32(b, 32, static_cast<uint64_t>(std::llround(std::max(0.0, g.amplitude_a()) * 1e6)));
        const double bias = p.amplitude_fraction > 0.0 ? g.amplitude_a() / p.amplitude_fraction : 0.0;
        put32(b, 34, static_cast<uint64_t>(std::llround(std::max(0.0, bias * p.amplitude_limit_fraction) * 1e6)));
        put16(b, 36, static_cast<uint16_t>(std::min(65535.0, std::round(g.design().crest_factor * 1e3))));
        put32(b, 37, static_cast<uint64_t>(std::llround(std::max(0.0, g.abort_orbit_m()) * 1e9)));
      } else {
        put16(b, 21, static_cast<uint16_t>(SweepRefusal::not_configured));
      }
      return true;
    }
    case regs::orbit_radius_nm:
      for (size_t i = 0; i < 2; ++i) put32(b, 2 * i, static_cast<uint64_t>(std::max(0.0, st.orbit_radius_m[i] * 1e9)));
      for (size_t i = 0; i < 4; ++i) put_i32(b, 4 + 2 * i, st.xy_m[i] * 1e9);
      for (size_t i = 0; i < 4; ++i)
        put16(b, 12 + i, static_cast<uint16_t>(static_cast<int16_t>(std::clamp(st.current_demand_a[i] * 1e3, -32767.0, 32767.0))));
      return true;
    case regs::loop_periods: {
      const LoopStats ls = src_.loop_stats ? src_.loop_stats() : LoopStats{};
      put64(b, 0, ls.periods);
      put64(b, 4, ls.overruns);
      put32(b, 8, static_cast<uint64_t>(ls.max_latency_ns));
      put32(b, 10, static_cast<uint64_t>(ls.mean_latency_ns()));
      put32(b, 12, static_cast<uint64_t>(ls.latency_quantile_ns(0.99)));
      put32(b, 14, static_cast<uint64_t>(ls.max_work_ns));
      const int64_t delay[] = {ls.delay_quantile_ns(0.5), ls.delay_quantile_ns(0.99), ls.delay_quantile_ns(0.999),
                               ls.max_delay_ns, static_cast<int64_t>(ls.mean_delay_ns()), ls.max_read_ns,
                               ls.max_step_ns, ls.max_write_ns};
      for (size_t i = 0; i < 8; ++i) put32(b, 16 + 2 * i, static_cast<uint64_t>(std::max<int64_t>(0, delay[i])));
      return true;
    }
    case regs::can_stats: {
      const hal::CanStats c = src_.can_stats ? src_.can_stats() : hal::CanStats{};
      const fieldbus::FieldBusCounters f = src_.fieldbus ? src_.fieldbus() : fieldbus::FieldBusCounters{};
      const LinkCounters l = src_.link ? src_.link() : LinkCounters{};
      const uint64_t can[] = {c.tx_frames, c.rx_frames, c.tx_dropped, c.rx_dropped, c.error_frames, c.bus_off_events,
                              c.malformed + f.malformed};
      for (size_t i = 0; i < 7; ++i) put32(b, 2 * i, can[i]);
      const uint64_t fb[] = {f.samples, f.stale_periods, f.malformed, f.node_timeouts, f.amp_faults, f.tx_failures};
      for (size_t i = 0; i < 6; ++i) put32(b, 0x10 + 2 * i, fb[i]);
      const uint64_t mb[] = {l.requests, l.exceptions, l.bad_frames, l.wrong_unit, l.connections, access_.refused_state,
                             access_.illegal_address};
      for (size_t i = 0; i < 7; ++i) put32(b, 0x20 + 2 * i, mb[i]);
      return true;
    }
    case regs::access_stats: {
      const LinkCounters l = src_.link ? src_.link() : LinkCounters{};
      const uint64_t a[] = {access_.arms,          access_.arm_key_mismatch, access_.commands,
                            access_.refused_not_armed, access_.refused_state, access_.refused_value,
                            l.refused_connections};
      for (size_t i = 0; i < 7; ++i) put32(b, 2 * i, a[i]);
      return true;
    }
    case regs::storage_stats: {
      const StoreCounters c = src_.storage ? src_.storage() : StoreCounters{};
      const uint64_t a[] = {c.written, c.refused, c.dropped_oldest, c.write_errors, c.no_space,
                            c.retries, c.pending,  c.lost,           wear_store_failures_};
      for (size_t i = 0; i < 9; ++i) put32(b, 2 * i, a[i]);
      return true;
    }
    case regs::arm: {
      const int64_t left_ns = src_.arm_window_ns - (now_ns() - armed_at_ns_);
      const bool armed = armed_op_ != regs::op_none && left_ns >= 0;
      put16(b, 0, armed ? armed_op_ : 0);
      put16(b, 1, armed ? static_cast<uint16_t>(std::min<int64_t>(65535, left_ns / 1'000'000)) : 0);
      return true;
    }
    case regs::command:
      put16(b, 0, command_result_);
      return true;
    case regs::event_count: {
      refresh_events();
      put16(b, 0, static_cast<uint16_t>(std::min<size_t>(events_.size(), 0xFFFF)));
      put16(b, 1, list_version_);
      put16(b, 2, browse_index_);
      if (browse_index_ < events_.size()) {
        const EventEntry& e = events_[browse_index_];
        put32(b, 3, e.size);
        put32(b, 5, e.crc);
        put_string(b, 7, e.name, 16);
      }
      return true;
    }
    case regs::dl_select:
      return true;  // selection reads back as zero (write-mostly)
    case regs::dl_status: {
      put16(b, 0, dl_status_);
      put32(b, regs::dl_block - regs::dl_status, dl_block_);
      put32(b, regs::dl_total_bytes - regs::dl_status, dl_bytes_.size());
      if (dl_status_ == regs::dl_ok) {
        const size_t from = static_cast<size_t>(dl_block_) * k_block_bytes;
        const size_t n = std::min<size_t>(k_block_bytes, dl_bytes_.size() - from);
        put16(b, 1, static_cast<uint16_t>(n));
        put32(b, 2, crc32c(std::span<const uint8_t>(dl_bytes_.data() + from, n)));
        for (size_t i = 0; i < n; ++i) {
          const size_t r = regs::dl_data - regs::dl_status + i / 2;
          b[r] = static_cast<uint16_t>(b[r] | (i % 2 == 0 ? dl_bytes_[from + i] << 8 : dl_bytes_[from + i]));
        }
      }
      return true;
    }
    case regs::wear_present: {
      const WearStore* w = src_.wear;
      const bool present = w && w->has_record();
      put16(b, 0, present ? 1 : 0);
      if (present) {
        const WearRecord& r = w->record();
        put32(b, 1, r.sequence);
        put32(b, 3, r.event_count);
        put32(b, 5, crc32c(w->encoded()));
        put32(b, 7, static_cast<uint64_t>(std::max(0.0f, r.last_friction_coefficient) * 1e6f));
        put64(b, 9, static_cast<uint64_t>(r.updated_unix_s));
        for (size_t i = 0; i < 2; ++i) {
          put32(b, 13 + 2 * i, static_cast<uint64_t>(std::max(0.0f, r.bearing[i].life_used_fraction) * 1e6f));
          put32(b, 17 + 2 * i, static_cast<uint64_t>(std::max(0.0f, r.bearing[i].peak_force_n)));
        }
      }
      put32(b, 21, w ? w->generation() : 0);
      put16(b, 23, static_cast<uint16_t>(src_.wear_corrupt_at_start));
      return true;
    }
    case regs::wb_control:
      put16(b, 0, wb_session_);
      put32(b, 1, wb_size_);
      put32(b, 3, wb_crc_);
      put32(b, 5, wb_received_);
      put16(b, 7, static_cast<uint16_t>(wb_result_));
      put32(b, 8, src_.wear && src_.wear->has_record() ? src_.wear->record().sequence : 0);
      return true;
    default:
      return false;
  }
}

hal::RegisterHandler::Status RegisterMap::read_registers(uint16_t address, std::span<uint16_t> out) {
  const uint32_t end = static_cast<uint32_t>(address) + out.size();
  uint32_t a = address;
  Block block;
  while (a < end) {
    const Range* r = nullptr;
    for (const Range& k : k_readable)
      if (a >= k.start && a < k.end) r = &k;
    if (!r) {
      ++access_.illegal_address;
      return illegal_address;
    }
    if (!render(r->start, r->end, block)) return device_failure;
    const uint32_t stop = std::min<uint32_t>(end, r->end);
    for (uint32_t i = a; i < stop; ++i) out[i - address] = block[i - r->start];
    a = stop;
  }
  return ok;
}

hal::RegisterHandler::Status RegisterMap::write_registers(uint16_t address, std::span<const uint16_t> v) {
  Status st = ok;
  switch (address) {
    case regs::arm: st = write_arm(v); break;
    case regs::command: st = write_command(v); break;
    case regs::event_browse_index:
      if (v.size() != 1) return refuse_value();
      browse_index_ = v[0];
      return ok;
    case regs::event_delete: st = write_delete(v); break;
    case regs::dl_select: st = write_select(v); break;
    case regs::wb_control: st = write_wb_control(v); break;
    case regs::wb_chunk: st = write_wb_chunk(v); break;
    default:
      ++access_.illegal_address;
      return illegal_address;
  }
  if (st == illegal_value) ++access_.refused_value;
  return st;
}

hal::RegisterHandler::Status RegisterMap::write_arm(std::span<const uint16_t> v) {
  // Only an accepted arm replaces the one in place: a refused arm (wrong key, bad operation)
  // leaves it, so that a stray client cannot cancel an operator's arm.
  if (v.size() != 3) return illegal_value;
  if (src_.arm_key == 0) {  // the board file gives no key: no commands over Modbus
    ++access_.refused_not_armed;
    return illegal_function;
  }
  const uint16_t op = v[2];
  const bool known = (op >= regs::op_levitate && op <= regs::op_sweep_abort) || op == regs::op_event_delete ||
                     op == regs::op_wear_commit;
  if (!known) return illegal_value;
  if (get32(v, 0) != src_.arm_key) {
    ++access_.arm_key_mismatch;
    return illegal_value;
  }
  armed_op_ = op;
  armed_at_ns_ = now_ns();
  ++access_.arms;
  return ok;
}

hal::RegisterHandler::Status RegisterMap::write_command(std::span<const uint16_t> v) {
  if (v.size() != 1 || v[0] < regs::op_levitate || v[0] > regs::op_sweep_abort) return illegal_value;
  if (v[0] == regs::k_command_sweep_start || v[0] == regs::k_command_sweep_abort) return write_sweep_command(v[0]);
  if (!take_arm(v[0])) return illegal_function;
  if (!state_allows(v[0])) {
    ++access_.refused_state;
    return busy;
  }
  if (v[0] == regs::k_command_capture) {
    if (!src_.manual_capture || !src_.manual_capture()) return device_failure;
    ++access_.commands;
    command_result_ = 1;
    return ok;
  }
  if (!src_.supervisor) return device_failure;
  const bool posted = src_.supervisor->post(static_cast<Command>(v[0]));
  command_result_ = posted ? 1 : 2;
  if (posted) ++access_.commands;
  return posted ? ok : busy;
}

// Sweep start / abort: armed like every command; a start is checked against the loop's state
// here (exception 6 with the reason counted by the sweep) and again by the loop when it takes it.
hal::RegisterHandler::Status RegisterMap::write_sweep_command(uint16_t op) {
  const bool armed = take_arm(op);
  if (!src_.supervisor) return armed ? device_failure : illegal_function;
  SweepGenerator& g = src_.supervisor->sweep();
  if (!armed) {
    if (op == regs::k_command_sweep_start) g.count_refusal(SweepRefusal::not_armed);
    return illegal_function;
  }
  if (op == regs::k_command_sweep_abort) {
    src_.supervisor->request_sweep_abort();
    ++access_.commands;
    command_result_ = 1;
    return ok;
  }
  const SweepRefusal r = src_.supervisor->sweep_start_refusal();
  if (r != SweepRefusal::none) {
    g.count_refusal(r);
    ++access_.refused_state;
    command_result_ = 2;
    return busy;
  }
  src_.supervisor->request_sweep_start();
  ++access_.commands;
  command_result_ = 1;
  return ok;
}

hal::RegisterHandler::Status RegisterMap::write_delete(std::span<const uint16_t> v) {
  if (v.size() != 3) return illegal_value;
  if (!take_arm(regs::op_event_delete)) return illegal_function;
  if (!state_allows(regs::op_event_delete)) {
    ++access_.refused_state;
    return busy;
  }
  refresh_events();
  if (!src_.events || v[0] >= events_.size() || events_[v[0]].crc != get32(v, 1)) return illegal_value;
  if (!src_.events->remove(events_[v[0]].name)) return device_failure;
  refresh_events();
  ++access_.commands;
  return ok;
}

hal::RegisterHandler::Status RegisterMap::write_select(std::span<const uint16_t> v) {
  if (v.size() != 3 && v.size() != 5) return illegal_value;
  const uint16_t index = v[0];
  const uint32_t crc = get32(v, 1);
  dl_block_ = v.size() == 5 ? get32(v, 3) : 0;
  std::string name;
  if (index == regs::k_wear_item_index) {
    if (!src_.wear || !src_.wear->has_record()) {
      dl_status_ = regs::dl_stale;
      return ok;
    }
    name = "\x01wear";
    if (dl_name_ != name || dl_crc_ != crc32c(src_.wear->encoded())) {
      dl_bytes_ = src_.wear->encoded();
      dl_name_ = name;
      dl_crc_ = crc32c(dl_bytes_);
    }
  } else {
    refresh_events();
    if (index >= events_.size()) {
      dl_status_ = regs::dl_stale;
      return ok;
    }
    EventEntry& e = events_[index];
    // Block 0 starts (or restarts) a download: read the file afresh so that a file rewritten
    // under the same name is never served from an old copy.
    if (dl_block_ == 0 || dl_name_ != e.name || dl_crc_ != e.crc) {
      std::string err;
      if (!src_.events->read(e.name, dl_bytes_, err)) {
        dl_status_ = regs::dl_read_error;
        dl_name_.clear();
        return ok;
      }
      dl_name_ = e.name;
      dl_crc_ = crc32c(dl_bytes_);
      e.size = static_cast<uint32_t>(dl_bytes_.size());
      e.crc = dl_crc_;  // the file changed since it was listed: the host sees "stale" and re-lists
    }
  }
  if (crc != dl_crc_) dl_status_ = regs::dl_stale;
  else if (static_cast<uint64_t>(dl_block_) * k_block_bytes >= dl_bytes_.size() && !(dl_block_ == 0 && dl_bytes_.empty()))
    dl_status_ = regs::dl_past_end;
  else dl_status_ = regs::dl_ok;
  return ok;
}

hal::RegisterHandler::Status RegisterMap::write_wb_control(std::span<const uint16_t> v) {
  if (v.empty()) return illegal_value;
  switch (v[0]) {
    case regs::wb_begin: {
      if (v.size() != 5) return illegal_value;
      const uint32_t size = get32(v, 1), crc = get32(v, 3);
      if (size == 0 || size > wb_staging_.size()) return illegal_value;
      // Same announcement as the session in progress: resume it (the host reads wb_received).
      if (!(wb_session_ != regs::wb_idle && size == wb_size_ && crc == wb_crc_)) {
        wb_size_ = size;
        wb_crc_ = crc;
        wb_received_ = 0;
      }
      wb_session_ = wb_received_ == wb_size_ ? regs::wb_complete : regs::wb_receiving;
      return ok;
    }
    case regs::wb_commit: {
      if (v.size() != 1) return illegal_value;
      if (!take_arm(regs::op_wear_commit)) return illegal_function;
      if (!state_allows(regs::op_wear_commit)) {
        ++access_.refused_state;
        wb_result_ = WriteBackResult::refused_unsafe;
        return busy;
      }
      if (wb_session_ == regs::wb_idle || wb_received_ != wb_size_) {
        wb_result_ = WriteBackResult::incomplete;
        return illegal_value;
      }
      const std::vector<uint8_t> bytes(wb_staging_.begin(), wb_staging_.begin() + wb_size_);
      if (crc32c(bytes) != wb_crc_) {
        wb_result_ = WriteBackResult::checksum_mismatch;
        wb_session_ = regs::wb_idle;
        return illegal_value;
      }
      if (!src_.wear) return device_failure;
      std::string detail;
      wb_result_ = src_.wear->accept(bytes, detail);
      // A storage failure keeps the complete session: the host re-arms and commits again
      // without resending the bytes.
      if (wb_result_ != WriteBackResult::storage_failed) wb_session_ = regs::wb_idle;
      if (wb_result_ == WriteBackResult::accepted) {
        ++access_.commands;
        return ok;
      }
      if (wb_result_ == WriteBackResult::storage_failed) {
        // The old record stays the newest generation; the host may commit the same bytes again.
        ++wear_store_failures_;
        return device_failure;
      }
      return illegal_value;
    }
    case regs::wb_abort:
      if (v.size() != 1) return illegal_value;
      wb_session_ = regs::wb_idle;
      wb_received_ = 0;
      wb_result_ = WriteBackResult::aborted;
      return ok;
    default:
      return illegal_value;
  }
}

hal::RegisterHandler::Status RegisterMap::write_wb_chunk(std::span<const uint16_t> v) {
  if (v.size() < 4 || wb_session_ == regs::wb_idle) return illegal_value;
  const uint32_t offset = get32(v, 0);
  const uint32_t n = v[2];
  if (n == 0 || n > regs::k_chunk_bytes || n > 2 * (v.size() - 3) || offset > wb_received_ ||
      static_cast<uint64_t>(offset) + n > wb_size_)
    return illegal_value;
  for (uint32_t i = 0; i < n; ++i) {
    const uint16_t w = v[3 + i / 2];
    wb_staging_[offset + i] = static_cast<uint8_t>(i % 2 == 0 ? w >> 8 : w & 0xFF);
  }
  wb_received_ = std::max(wb_received_, offset + n);
  wb_session_ = wb_received_ == wb_size_ ? regs::wb_complete : regs::wb_receiving;
  return ok;
}

}  // namespace amb::fw
