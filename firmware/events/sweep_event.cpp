#include "firmware/events/sweep_event.hpp"

#include <cinttypes>
#include <cstdio>

#include "firmware/board/board.hpp"
#include "firmware/capture/frozen_event.hpp"
#include "firmware/common/byte_codec.hpp"
#include "firmware/common/crc32.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/event_meta_fields.hpp"

namespace amb::fw {

namespace {

// The sweep header (96 bytes) without the counts, which the codec writes and checks itself.
template <class Coder, class Ev>
void header_fields(Coder& c, Ev& e) {
  c.u8(e.injection);
  c.u8(e.excitation);
  c.u8_of(e.aborted);
  c.u8_of(e.abort_reason);
}
template <class Coder, class Ev>
void plan_fields(Coder& c, Ev& e) {
  c.u32(e.samples_per_period);
  c.u32(e.settle_periods);
  c.u32(e.recorded_periods);
}
template <class Coder, class Ev>
void value_fields(Coder& c, Ev& e) {
  c.f64(e.speed_hz);
  c.f64(e.bias_current_a);
  c.f64(e.loop_delay_periods);
  c.f64(e.amplitude_a);
  c.f64(e.crest_factor);
  c.f64(e.abort_orbit_m);
  c.f64(e.amplitude_limit_a);
  c.i64(e.start_t_ns);
  c.u64(e.start_seq);
}


}  // namespace

SweepEvent make_sweep_event(const SweepCaptureView& v, const board::BoardConfig& b, uint64_t event_number) {
  // The metadata of a drop event of this board (calibration, controller), then the sweep's.
  FrozenEvent none;
  EventRecord base = make_event_record(none, b, event_number);
  SweepEvent e;
  e.meta = base.meta;
  e.meta.pre_trigger_s = 0.0;
  e.meta.post_trigger_s = 0.0;
  e.meta.cause = TriggerCause::none;
  e.meta.trigger_seq = v.start_seq;
  e.meta.trigger_t_ns = v.start_t_ns;
  e.meta.speed_at_trigger_hz = v.speed_hz;
  e.meta.first_t_ns = v.start_t_ns;
  e.meta.last_t_ns = v.end_t_ns;
  e.injection = 0;
  e.excitation = 0;
  e.aborted = v.aborted;
  e.abort_reason = v.abort_reason;
  e.samples_per_period = v.samples_per_period;
  e.settle_periods = v.settle_periods;
  e.recorded_periods = v.recorded_periods;
  e.speed_hz = v.speed_hz;
  e.bias_current_a = b.plant.amb[0].bias_current_a;
  e.loop_delay_periods = b.loop_delay_periods;
  e.amplitude_a = v.amplitude_a;
  e.crest_factor = v.crest_factor;
  e.abort_orbit_m = b.sweep.abort_clearance_fraction * std::min(b.plant.aux[0].clearance_m, b.plant.aux[1].clearance_m);
  e.amplitude_limit_a = b.sweep.amplitude_limit_fraction * e.bias_current_a;
  e.start_t_ns = v.start_t_ns;
  e.start_seq = v.start_seq;
  e.bins.assign(v.bins.begin(), v.bins.end());
  for (uint32_t i = 0; i < v.axes_done; ++i) {
    SweepAxisData a;
    a.axis = v.axes[i];
    auto copy = [&](uint32_t ch, std::vector<float>& to) {
      const auto s = v.channel(i, ch);
      to.assign(s.begin(), s.end());
    };
    copy(0, a.excitation_a);
    copy(1, a.controller_output_a);
    copy(2, a.summing_point_a);
    copy(3, a.sensor_m);
    e.axes.push_back(std::move(a));
  }
  return e;
}

std::vector<uint8_t> encode_sweep_event(const SweepEvent& e) {
  const uint64_t per_axis = static_cast<uint64_t>(e.recorded_periods) * e.samples_per_period;
  const uint64_t total = sweep_event_file_bytes(e.bins.size(), e.axes.size(), per_axis);
  std::vector<uint8_t> out;
  out.reserve(static_cast<size_t>(total));
  ByteWriter w(out);
  w.u8('A'); w.u8('M'); w.u8('B'); w.u8('E');
  w.u16(k_sweep_event_format_version);
  w.u16(static_cast<uint16_t>(EventKind::sweep));
  w.u64(total);
  w.u32(static_cast<uint32_t>(k_event_meta_bytes_v1));
  w.u32(0);  // drop samples: none
  w.u32(static_cast<uint32_t>(k_event_sample_bytes_v3));
  w.u32(0);  // diagnosis: none
  meta_fields(w, e.meta);
  header_fields(w, e);
  w.u8(static_cast<uint8_t>(e.axes.size()));
  w.zeros(3);
  plan_fields(w, e);
  w.u32(static_cast<uint32_t>(e.bins.size()));
  value_fields(w, e);
  for (uint32_t k : e.bins) w.u32(k);
  for (const SweepAxisData& a : e.axes) {
    w.u8(a.axis);
    w.zeros(3);
    w.u32(static_cast<uint32_t>(per_axis));
    for (const auto* ch : {&a.excitation_a, &a.controller_output_a, &a.summing_point_a, &a.sensor_m})
      for (size_t i = 0; i < per_axis; ++i) w.f32(i < ch->size() ? (*ch)[i] : 0.0f);
  }
  w.u32(crc32(out));
  return out;
}

bool decode_sweep_event(std::span<const uint8_t> bytes, SweepEvent& out, std::string& error) {
  EventKind kind = EventKind::drop;
  uint16_t version = 0;
  if (!peek_event_kind(bytes, kind, version, error)) return false;
  const size_t size = bytes.size();
  if (size < k_event_preamble_bytes) {
    error = "truncated: " + std::to_string(size) + " bytes, the preamble alone needs " + std::to_string(k_event_preamble_bytes);
    return false;
  }
  ByteReader pre(bytes.data(), size);
  pre.u64();
  const uint64_t total = pre.u64();
  if (!check_event_frame(bytes, total, error)) return false;
  if (kind != EventKind::sweep) {
    error = "not a sweep event: version " + std::to_string(version) + ", record kind " +
            std::to_string(static_cast<int>(kind)) + " (" + to_string(kind) + ")";
    return false;
  }
  const uint32_t meta_bytes = pre.u32(), count = pre.u32(), sample_bytes = pre.u32(), diag_bytes = pre.u32();
  if (meta_bytes != k_event_meta_bytes_v1 || count != 0 || sample_bytes != k_event_sample_bytes_v3 || diag_bytes != 0) {
    error = "inconsistent sizes: a sweep event has metadata 616 B, no drop samples (84 B each) and no diagnosis; "
            "header says metadata " + std::to_string(meta_bytes) + " B, " + std::to_string(count) + " samples of " +
            std::to_string(sample_bytes) + " B, diagnosis " + std::to_string(diag_bytes) + " B";
    return false;
  }
  if (total < k_event_preamble_bytes + k_event_meta_bytes_v1 + k_sweep_header_bytes + 4) {
    error = "truncated: declared length " + std::to_string(total) + " is shorter than a sweep event's headers";
    return false;
  }
  SweepEvent e;
  e.format_version = version;
  ByteReader rd(bytes.data() + k_event_preamble_bytes, size - k_event_preamble_bytes - 4);
  meta_fields(rd, e.meta);
  header_fields(rd, e);
  const uint8_t axis_count = rd.u8();
  rd.zeros(3);
  plan_fields(rd, e);
  const uint32_t lines = rd.u32();
  value_fields(rd, e);
  const uint64_t per_axis = static_cast<uint64_t>(e.recorded_periods) * e.samples_per_period;
  if (e.injection > 1 || e.excitation > 1 || static_cast<uint8_t>(e.abort_reason) > static_cast<uint8_t>(SweepAbort::fault) ||
      e.aborted != (e.abort_reason != SweepAbort::none)) {
    error = "bad sweep header: injection " + std::to_string(e.injection) + ", excitation " + std::to_string(e.excitation) +
            ", aborted " + std::to_string(e.aborted) + " with reason " + std::to_string(static_cast<int>(e.abort_reason));
    return false;
  }
  if (e.samples_per_period < 4 || e.recorded_periods == 0 || axis_count > 4 || lines == 0 ||
      lines > e.samples_per_period / 2) {
    error = "bad sweep header: samples_per_period " + std::to_string(e.samples_per_period) + ", recorded_periods " +
            std::to_string(e.recorded_periods) + ", " + std::to_string(axis_count) + " axes, " + std::to_string(lines) +
            " lines";
    return false;
  }
  if (total != sweep_event_file_bytes(lines, axis_count, per_axis)) {
    error = "inconsistent sizes: " + std::to_string(lines) + " lines and " + std::to_string(axis_count) + " axes of " +
            std::to_string(per_axis) + " samples make " + std::to_string(sweep_event_file_bytes(lines, axis_count, per_axis)) +
            " B, the header declares " + std::to_string(total);
    return false;
  }
  e.bins.resize(lines);
  for (uint32_t& k : e.bins) k = rd.u32();
  for (size_t i = 0; i < e.bins.size(); ++i) {
    if (e.bins[i] == 0 || 2 * static_cast<uint64_t>(e.bins[i]) >= e.samples_per_period || (i > 0 && e.bins[i] <= e.bins[i - 1])) {
      error = "bad sweep header: line " + std::to_string(i) + " at bin " + std::to_string(e.bins[i]) +
              " (bins must ascend strictly inside 1 .. N/2 - 1, N = " + std::to_string(e.samples_per_period) + ")";
      return false;
    }
  }
  uint8_t seen = 0;
  e.axes.resize(axis_count);
  for (SweepAxisData& a : e.axes) {
    a.axis = rd.u8();
    rd.zeros(3);
    const uint32_t n = rd.u32();
    if (a.axis > 3 || (seen & (1u << a.axis)) != 0 || n != per_axis) {
      error = "bad sweep header: axis block for axis " + std::to_string(a.axis) + " with " + std::to_string(n) +
              " samples (axes 0..3, each once, recorded_periods x samples_per_period = " + std::to_string(per_axis) + ")";
      return false;
    }
    seen = static_cast<uint8_t>(seen | (1u << a.axis));
    for (auto* ch : {&a.excitation_a, &a.controller_output_a, &a.summing_point_a, &a.sensor_m}) {
      ch->resize(n);
      for (float& v : *ch) v = rd.f32();
    }
  }
  if (!rd.ok() || rd.remaining() != 0) {
    error = "inconsistent sizes: body does not match the declared layout";
    return false;
  }
  out = std::move(e);
  return true;
}

}  // namespace amb::fw
