#include "firmware/events/event_codec.hpp"

#include <array>
#include <cinttypes>
#include <cstdio>

#include "firmware/common/byte_codec.hpp"
#include "firmware/common/crc32.hpp"
#include "firmware/events/event_meta_fields.hpp"

namespace amb::fw {
namespace {

// The field lists of AMBE, each written once (byte_codec.hpp): Coder is ByteWriter (Rec const)
// or ByteReader. Layout and sizes: docs/event-format.md.

template <class Coder, class Sample>
void sample_fields(Coder& c, Sample& s, uint16_t version) {
  c.u64(s.seq);
  c.i64(s.t_ns);
  c.f32s(s.displacement_m);
  c.f32s(s.coil_current_a);
  c.f32s(s.current_demand_a);
  c.f32(s.speed_hz);
  c.f32(s.speed_command_hz);
  c.u8(s.state);
  c.u8(s.phase);
  c.u8(s.fault);
  c.u8(s.speed_quality);
  c.u32(s.flags);
  if (version >= 3) c.f32(s.tach_hz);
  else if constexpr (Coder::k_reads) s.tach_hz = -1.0f;  // older files: no tachometer channel recorded
}

template <class Coder, class Diag>
void diagnosis_fields(Coder& c, Diag& d) {
  c.u8_of(d.type);
  c.u8(d.cutoff_channels);
  c.u8(d.disturbance_channels);
  c.i8_of(d.misalignment_plane);
  c.zeros(4);
  c.f64(d.confidence);
  c.f64s(d.current_factor);
  c.f64(d.disturbance_frequency_hz);
  c.f64(d.disturbance_amplitude_a);
  c.f64(d.current_lead_s);
  c.f64(d.speed_hz);
  c.f64s(d.radius_1x_start_m);
  c.f64s(d.radius_1x_end_m);
  c.f64s(d.centre_shift_m);
  c.f64(d.misalignment_direction_deg);
  c.text(d.summary, 256, 255);
}

template <class Coder, class Analysis>
void analysis_fields(Coder& c, Analysis& a) {
  c.u8(a.speed_source);
  c.u8_of(a.speed_lost_at_trigger);
  c.u8_of(a.quick_look_valid);
  c.zeros(5);
  c.f64(a.speed_confidence_at_trigger);
  c.f64(a.quick_look_spin_hz);
  c.f64(a.aux_contact_constant_n_per_m1p5);
  c.f64(a.aux_dynamic_load_rating_n);
  for (auto& q : a.aux) {
    c.u8_of(q.valid);
    c.zeros(3);
    c.u32(q.samples_in_contact);
    c.f64(q.peak_force_n);
    c.f64(q.peak_angle_deg);
    c.f64(q.life_fraction);
    c.f64(q.contact_time_s);
  }
}

std::string hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08" PRIx32, v);
  return b;
}

}  // namespace

bool check_event_frame(std::span<const uint8_t> bytes, uint64_t declared_bytes, std::string& error) {
  const size_t size = bytes.size();
  // The length comes first (same offset in every version): a short file is reported as
  // truncated, not as a checksum error.
  if (size < declared_bytes) {
    error = "truncated: file has " + std::to_string(size) + " bytes, its header declares " + std::to_string(declared_bytes);
    return false;
  }
  if (size > declared_bytes) {
    error = "inconsistent sizes: file has " + std::to_string(size) + " bytes, its header declares " +
            std::to_string(declared_bytes) + " (trailing data)";
    return false;
  }
  if (declared_bytes < k_event_preamble_bytes + 4) {
    error = "truncated: declared length " + std::to_string(declared_bytes) + " is shorter than a header";
    return false;
  }
  const uint32_t stored = static_cast<uint32_t>(bytes[size - 4]) | (static_cast<uint32_t>(bytes[size - 3]) << 8) |
                          (static_cast<uint32_t>(bytes[size - 2]) << 16) | (static_cast<uint32_t>(bytes[size - 1]) << 24);
  const uint32_t computed = crc32(bytes.first(size - 4));
  if (stored != computed) {
    error = "bad checksum: stored CRC-32 " + hex32(stored) + ", computed " + hex32(computed) + " (file corrupted)";
    return false;
  }
  return true;
}

namespace {
std::vector<uint8_t> encode(const EventRecord& r, uint16_t version) {
  const size_t n = r.samples.size();
  const size_t diag_bytes = r.has_diagnosis ? k_event_diagnosis_bytes_v1 : 0;
  const size_t analysis_bytes = version >= 2 ? k_event_analysis_bytes_v2 : 0;
  const size_t sample_bytes = version >= 3 ? k_event_sample_bytes_v3 : k_event_sample_bytes_v1;
  const uint64_t total = k_event_preamble_bytes + k_event_meta_bytes_v1 + n * sample_bytes + diag_bytes +
                         analysis_bytes + 4;
  std::vector<uint8_t> out;
  out.reserve(static_cast<size_t>(total));
  ByteWriter w(out);
  w.u8('A'); w.u8('M'); w.u8('B'); w.u8('E');
  w.u16(version);
  w.u16(0);
  w.u64(total);
  w.u32(static_cast<uint32_t>(k_event_meta_bytes_v1));
  w.u32(static_cast<uint32_t>(n));
  w.u32(static_cast<uint32_t>(sample_bytes));
  w.u32(static_cast<uint32_t>(diag_bytes));
  meta_fields(w, r.meta);
  for (const LoopSample& s : r.samples) sample_fields(w, s, version);
  if (r.has_diagnosis) diagnosis_fields(w, r.diagnosis);
  const EventAnalysis analysis = r.has_analysis ? r.analysis : EventAnalysis{};
  if (version >= 2) analysis_fields(w, analysis);
  w.u32(crc32(out));
  return out;
}
}  // namespace

std::vector<uint8_t> encode_event(const EventRecord& r) { return encode(r, k_event_format_version); }
std::vector<uint8_t> encode_event_v1(const EventRecord& r) { return encode(r, 1); }
std::vector<uint8_t> encode_event_v2(const EventRecord& r) { return encode(r, 2); }

const char* to_string(EventKind k) {
  switch (k) {
    case EventKind::drop: return "drop";
    case EventKind::sweep: return "sweep";
  }
  return "?";
}

bool peek_event_kind(std::span<const uint8_t> bytes, EventKind& kind, uint16_t& version, std::string& error) {
  if (bytes.size() < 8) {
    error = "truncated: " + std::to_string(bytes.size()) + " bytes, the preamble alone needs " +
            std::to_string(k_event_preamble_bytes);
    return false;
  }
  if (bytes[0] != 'A' || bytes[1] != 'M' || bytes[2] != 'B' || bytes[3] != 'E') {
    error = "not an AMBE event file: magic is not \"AMBE\"";
    return false;
  }
  version = static_cast<uint16_t>(bytes[4] | bytes[5] << 8);
  const auto k = static_cast<uint16_t>(bytes[6] | bytes[7] << 8);
  if (version < k_event_format_oldest_read || version > k_event_format_newest_read) {
    error = "unsupported version " + std::to_string(version) + " (this reader reads AMBE versions " +
            std::to_string(k_event_format_oldest_read) + " to " + std::to_string(k_event_format_newest_read) + ")";
    return false;
  }
  if (version < 4) {
    kind = EventKind::drop;
    return true;
  }
  if (k != static_cast<uint16_t>(EventKind::drop) && k != static_cast<uint16_t>(EventKind::sweep)) {
    error = "unknown record kind " + std::to_string(k) + " (this reader knows 0 drop, 1 sweep)";
    return false;
  }
  kind = static_cast<EventKind>(k);
  return true;
}

bool decode_event(std::span<const uint8_t> bytes, EventRecord& out, std::string& error) {
  const size_t size = bytes.size();
  if (size < 16) {
    error = "truncated: " + std::to_string(size) + " bytes, the preamble alone needs " +
            std::to_string(k_event_preamble_bytes);
    return false;
  }
  if (bytes[0] != 'A' || bytes[1] != 'M' || bytes[2] != 'B' || bytes[3] != 'E') {
    error = "not an AMBE event file: magic is not \"AMBE\"";
    return false;
  }
  ByteReader pre(bytes.data(), size);
  pre.u32();
  const uint16_t version = pre.u16();
  pre.u16();
  const uint64_t total = pre.u64();
  if (!check_event_frame(bytes, total, error)) return false;
  if (version < k_event_format_oldest_read || version > k_event_format_newest_read) {
    error = "unsupported version " + std::to_string(version) + " (this reader reads AMBE versions " +
            std::to_string(k_event_format_oldest_read) + " to " + std::to_string(k_event_format_newest_read) + ")";
    return false;
  }
  if (version >= 4) {
    EventKind kind = EventKind::drop;
    uint16_t v = 0;
    if (!peek_event_kind(bytes, kind, v, error)) return false;
    if (kind != EventKind::drop) {
      error = std::string("not a drop event: record kind ") + std::to_string(static_cast<int>(kind)) + " (" +
              to_string(kind) + "); read it with decode_sweep_event";
      return false;
    }
  }
  const size_t analysis_bytes = version >= 2 ? k_event_analysis_bytes_v2 : 0;
  const uint32_t meta_bytes = pre.u32();
  const uint32_t count = pre.u32();
  const uint32_t sample_bytes = pre.u32();
  const uint32_t diag_bytes = pre.u32();
  const size_t expected_sample_bytes = version >= 3 ? k_event_sample_bytes_v3 : k_event_sample_bytes_v1;
  if (meta_bytes != k_event_meta_bytes_v1 || sample_bytes != expected_sample_bytes ||
      (diag_bytes != 0 && diag_bytes != k_event_diagnosis_bytes_v1) ||
      total != k_event_preamble_bytes + meta_bytes + static_cast<uint64_t>(count) * sample_bytes + diag_bytes +
                   analysis_bytes + 4) {
    error = "inconsistent sizes: metadata " + std::to_string(meta_bytes) + " B, " + std::to_string(count) +
            " samples of " + std::to_string(sample_bytes) + " B, diagnosis " + std::to_string(diag_bytes) +
            " B do not add up to " + std::to_string(total) + " B for version " + std::to_string(version);
    return false;
  }
  EventRecord r;
  ByteReader rd(bytes.data() + k_event_preamble_bytes, size - k_event_preamble_bytes - 4);
  meta_fields(rd, r.meta);
  r.samples.resize(count);
  for (LoopSample& s : r.samples) sample_fields(rd, s, version);
  r.has_diagnosis = diag_bytes != 0;
  if (r.has_diagnosis) diagnosis_fields(rd, r.diagnosis);
  r.has_analysis = version >= 2;
  if (r.has_analysis) analysis_fields(rd, r.analysis);
  r.format_version = version;
  if (!rd.ok() || rd.remaining() != 0) {
    error = "inconsistent sizes: body does not match the declared layout";
    return false;
  }
  if (count > 0 && r.meta.trigger_index >= count) {
    error = "inconsistent metadata: trigger_index " + std::to_string(r.meta.trigger_index) + " >= " +
            std::to_string(count) + " samples";
    return false;
  }
  out = std::move(r);
  return true;
}

}  // namespace amb::fw
