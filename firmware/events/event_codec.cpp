#include "firmware/events/event_codec.hpp"

#include <array>
#include <cinttypes>
#include <cstdio>

#include "firmware/common/byte_codec.hpp"
#include "firmware/common/crc32.hpp"

namespace amb::fw {
namespace {

void write_meta(ByteWriter& w, const EventMetadata& m) {
  w.str(m.board_name, 64);
  w.str(m.rig_name, 64);
  w.str(m.firmware_version, 32);
  w.str(m.board_source, 128);
  w.u64(m.event_number);
  w.u64(m.capture_number);
  w.f64(m.rate_hz);
  w.f64(m.pre_trigger_s);
  w.f64(m.post_trigger_s);
  w.u8(static_cast<uint8_t>(m.cause));
  w.u8(m.cutoff_channels);
  w.u16(0);
  w.u32(m.cause_mask);
  w.u32(m.trigger_index);
  w.u32(m.seq_gaps);
  w.u64(m.trigger_seq);
  w.i64(m.trigger_t_ns);
  w.f64(m.speed_at_trigger_hz);
  w.i64(m.first_t_ns);
  w.i64(m.last_t_ns);
  w.u64(m.events_lost_before);
  for (double g : {m.kp_n_per_m, m.ki_n_per_m_s, m.kd_n_s_per_m, m.derivative_filter_hz, m.integrator_limit_n,
                   m.current_limit_a})
    w.f64(g);
  for (const auto& s : m.sensors) { w.f64(s.axial_m); w.f64(s.angle_deg); }
  for (const auto& a : m.actuators) { w.f64(a.axial_m); w.f64(a.angle_deg); w.f64(a.ki_n_per_a); }
  w.f64(m.orbit_trigger_limit_m);
  w.f64(m.current_trigger_limit_a);
}

void read_meta(ByteReader& r, EventMetadata& m) {
  m.board_name = r.str(64);
  m.rig_name = r.str(64);
  m.firmware_version = r.str(32);
  m.board_source = r.str(128);
  m.event_number = r.u64();
  m.capture_number = r.u64();
  m.rate_hz = r.f64();
  m.pre_trigger_s = r.f64();
  m.post_trigger_s = r.f64();
  m.cause = static_cast<TriggerCause>(r.u8());
  m.cutoff_channels = r.u8();
  (void)r.u16();
  m.cause_mask = r.u32();
  m.trigger_index = r.u32();
  m.seq_gaps = r.u32();
  m.trigger_seq = r.u64();
  m.trigger_t_ns = r.i64();
  m.speed_at_trigger_hz = r.f64();
  m.first_t_ns = r.i64();
  m.last_t_ns = r.i64();
  m.events_lost_before = r.u64();
  for (double* g : {&m.kp_n_per_m, &m.ki_n_per_m_s, &m.kd_n_s_per_m, &m.derivative_filter_hz, &m.integrator_limit_n,
                    &m.current_limit_a})
    *g = r.f64();
  for (auto& s : m.sensors) { s.axial_m = r.f64(); s.angle_deg = r.f64(); }
  for (auto& a : m.actuators) { a.axial_m = r.f64(); a.angle_deg = r.f64(); a.ki_n_per_a = r.f64(); }
  m.orbit_trigger_limit_m = r.f64();
  m.current_trigger_limit_a = r.f64();
}

void write_sample(ByteWriter& w, const LoopSample& s, uint16_t version) {
  w.u64(s.seq);
  w.i64(s.t_ns);
  for (float v : s.displacement_m) w.f32(v);
  for (float v : s.coil_current_a) w.f32(v);
  for (float v : s.current_demand_a) w.f32(v);
  w.f32(s.speed_hz);
  w.f32(s.speed_command_hz);
  w.u8(s.state);
  w.u8(s.phase);
  w.u8(s.fault);
  w.u8(s.speed_quality);
  w.u32(s.flags);
  if (version >= 3) w.f32(s.tach_hz);
}

void read_sample(ByteReader& r, LoopSample& s, uint16_t version) {
  s.seq = r.u64();
  s.t_ns = r.i64();
  for (float& v : s.displacement_m) v = r.f32();
  for (float& v : s.coil_current_a) v = r.f32();
  for (float& v : s.current_demand_a) v = r.f32();
  s.speed_hz = r.f32();
  s.speed_command_hz = r.f32();
  s.state = r.u8();
  s.phase = r.u8();
  s.fault = r.u8();
  s.speed_quality = r.u8();
  s.flags = r.u32();
  s.tach_hz = version >= 3 ? r.f32() : -1.0f;  // older files: no tachometer channel recorded
}

void write_diagnosis(ByteWriter& w, const diag::Diagnosis& d) {
  w.u8(static_cast<uint8_t>(d.type));
  w.u8(d.cutoff_channels);
  w.u8(d.disturbance_channels);
  w.u8(static_cast<uint8_t>(static_cast<int8_t>(d.misalignment_plane)));
  w.u32(0);
  w.f64(d.confidence);
  for (double f : d.current_factor) w.f64(f);
  w.f64(d.disturbance_frequency_hz);
  w.f64(d.disturbance_amplitude_a);
  w.f64(d.current_lead_s);
  w.f64(d.speed_hz);
  for (double v : d.radius_1x_start_m) w.f64(v);
  for (double v : d.radius_1x_end_m) w.f64(v);
  for (double v : d.centre_shift_m) w.f64(v);
  w.f64(d.misalignment_direction_deg);
  w.str(d.summary.substr(0, 255), 256);
}

void read_diagnosis(ByteReader& r, diag::Diagnosis& d) {
  d.type = static_cast<diag::FaultType>(r.u8());
  d.cutoff_channels = r.u8();
  d.disturbance_channels = r.u8();
  d.misalignment_plane = static_cast<int8_t>(r.u8());
  (void)r.u32();
  d.confidence = r.f64();
  for (double& f : d.current_factor) f = r.f64();
  d.disturbance_frequency_hz = r.f64();
  d.disturbance_amplitude_a = r.f64();
  d.current_lead_s = r.f64();
  d.speed_hz = r.f64();
  for (double& v : d.radius_1x_start_m) v = r.f64();
  for (double& v : d.radius_1x_end_m) v = r.f64();
  for (double& v : d.centre_shift_m) v = r.f64();
  d.misalignment_direction_deg = r.f64();
  d.summary = r.str(256);
}

void write_analysis(ByteWriter& w, const EventAnalysis& a) {
  w.u8(a.speed_source);
  w.u8(a.speed_lost_at_trigger ? 1 : 0);
  w.u8(a.quick_look_valid ? 1 : 0);
  w.u8(0);
  w.u32(0);
  w.f64(a.speed_confidence_at_trigger);
  w.f64(a.quick_look_spin_hz);
  w.f64(a.aux_contact_constant_n_per_m1p5);
  w.f64(a.aux_dynamic_load_rating_n);
  for (const AuxQuickLook& q : a.aux) {
    w.u8(q.valid ? 1 : 0);
    w.u8(0);
    w.u16(0);
    w.u32(q.samples_in_contact);
    w.f64(q.peak_force_n);
    w.f64(q.peak_angle_deg);
    w.f64(q.life_fraction);
    w.f64(q.contact_time_s);
  }
}

void read_analysis(ByteReader& r, EventAnalysis& a) {
  a.speed_source = r.u8();
  a.speed_lost_at_trigger = r.u8() != 0;
  a.quick_look_valid = r.u8() != 0;
  (void)r.u8();
  (void)r.u32();
  a.speed_confidence_at_trigger = r.f64();
  a.quick_look_spin_hz = r.f64();
  a.aux_contact_constant_n_per_m1p5 = r.f64();
  a.aux_dynamic_load_rating_n = r.f64();
  for (AuxQuickLook& q : a.aux) {
    q.valid = r.u8() != 0;
    (void)r.u8();
    (void)r.u16();
    q.samples_in_contact = r.u32();
    q.peak_force_n = r.f64();
    q.peak_angle_deg = r.f64();
    q.life_fraction = r.f64();
    q.contact_time_s = r.f64();
  }
}

std::string hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08" PRIx32, v);
  return b;
}

}  // namespace

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
  write_meta(w, r.meta);
  for (const LoopSample& s : r.samples) write_sample(w, s, version);
  if (r.has_diagnosis) write_diagnosis(w, r.diagnosis);
  if (version >= 2) write_analysis(w, r.has_analysis ? r.analysis : EventAnalysis{});
  w.u32(crc32(out));
  return out;
}
}  // namespace

std::vector<uint8_t> encode_event(const EventRecord& r) { return encode(r, k_event_format_version); }
std::vector<uint8_t> encode_event_v1(const EventRecord& r) { return encode(r, 1); }
std::vector<uint8_t> encode_event_v2(const EventRecord& r) { return encode(r, 2); }

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
  // The length comes first (same offset in every version): a short file is reported as
  // truncated, not as a checksum error.
  if (size < total) {
    error = "truncated: file has " + std::to_string(size) + " bytes, its header declares " + std::to_string(total);
    return false;
  }
  if (size > total) {
    error = "inconsistent sizes: file has " + std::to_string(size) + " bytes, its header declares " +
            std::to_string(total) + " (trailing data)";
    return false;
  }
  if (total < k_event_preamble_bytes + 4) {
    error = "truncated: declared length " + std::to_string(total) + " is shorter than a header";
    return false;
  }
  const uint32_t stored = static_cast<uint32_t>(bytes[size - 4]) | (static_cast<uint32_t>(bytes[size - 3]) << 8) |
                          (static_cast<uint32_t>(bytes[size - 2]) << 16) | (static_cast<uint32_t>(bytes[size - 1]) << 24);
  const uint32_t computed = crc32(bytes.first(size - 4));
  if (stored != computed) {
    error = "bad checksum: stored CRC-32 " + hex32(stored) + ", computed " + hex32(computed) + " (file corrupted)";
    return false;
  }
  if (version < k_event_format_oldest_read || version > k_event_format_version) {
    error = "unsupported version " + std::to_string(version) + " (this reader reads AMBE versions " +
            std::to_string(k_event_format_oldest_read) + " to " + std::to_string(k_event_format_version) + ")";
    return false;
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
  read_meta(rd, r.meta);
  r.samples.resize(count);
  for (LoopSample& s : r.samples) read_sample(rd, s, version);
  r.has_diagnosis = diag_bytes != 0;
  if (r.has_diagnosis) read_diagnosis(rd, r.diagnosis);
  r.has_analysis = version >= 2;
  if (r.has_analysis) read_analysis(rd, r.analysis);
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
