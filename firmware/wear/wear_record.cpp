#include "firmware/wear/wear_record.hpp"

#include <cmath>

#include "firmware/common/byte_codec.hpp"
#include "firmware/common/crc32.hpp"

namespace amb::fw {

namespace {
constexpr size_t k_name_width = 32;
constexpr size_t k_model_width = 64;
constexpr size_t k_name_offset = 12;  // magic, version, reserved, sequence

/// A fixed-width text field as the encoder writes it: printable ASCII, NUL-terminated within
/// the field, zero padding after the terminator. Anything else is refused (found by fuzzing:
/// such a record decoded but did not re-encode to the same bytes).
bool text_field_ok(const uint8_t* p, size_t width) {
  size_t n = 0;
  while (n < width && p[n] != 0) {
    if (p[n] < 0x20 || p[n] > 0x7E) return false;
    ++n;
  }
  if (n == width) return false;
  for (size_t i = n; i < width; ++i)
    if (p[i] != 0) return false;
  return true;
}

/// Loads, durations, energies, forces and fractions are finite and not negative.
bool quantity_ok(float v) { return std::isfinite(v) && v >= 0.0f; }

/// The record's fields after the header (magic, version, reserved), written once: Coder is
/// ByteWriter (Rec const) or ByteReader (firmware/common/byte_codec.hpp).
template <class Coder, class Rec>
void record_fields(Coder& c, Rec& r) {
  c.u32(r.sequence);
  c.text(r.board_name, k_name_width, k_name_width - 1);
  c.text(r.life_model, k_model_width, k_model_width - 1);
  c.u32(r.event_count);
  c.f32(r.last_friction_coefficient);
  c.i64(r.updated_unix_s);
  for (auto& b : r.bearing) {
    c.f32s(b.event_load_n);
    c.f32s(b.cumulative_load_n);
    c.f32(b.swing_s);
    c.f32(b.forward_rub_s);
    c.f32(b.backward_rub_s);
    c.f32(b.friction_energy_j);
    c.f32(b.peak_force_n);
    c.f32(b.life_used_fraction);
  }
}
}  // namespace

std::vector<uint8_t> encode_wear_record(const WearRecord& r) {
  std::vector<uint8_t> out;
  ByteWriter w(out);
  w.u32(WearRecord::k_magic);
  w.u16(WearRecord::k_version);
  w.u16(0);
  record_fields(w, r);
  w.u32(crc32(out));
  return out;
}


bool decode_wear_record(const std::vector<uint8_t>& bytes, WearRecord& out, std::string& error) {
  const size_t expected = wear_record_size();
  if (bytes.size() < 8) {
    error = "wear record truncated: " + std::to_string(bytes.size()) + " bytes";
    return false;
  }
  ByteReader h(bytes.data(), bytes.size());
  if (h.u32() != WearRecord::k_magic) {
    error = "not a wear record (bad magic)";
    return false;
  }
  const uint16_t version = h.u16();
  if (version != WearRecord::k_version) {
    error = "wear record version " + std::to_string(version) + " not supported (expected " +
            std::to_string(WearRecord::k_version) + ")";
    return false;
  }
  if (bytes.size() != expected) {
    error = "wear record has " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(expected) +
            (bytes.size() < expected ? " (truncated)" : " (trailing data)");
    return false;
  }
  const uint32_t stored = ByteReader(bytes.data() + expected - 4, 4).u32();
  const uint32_t computed = crc32(std::span<const uint8_t>(bytes.data(), expected - 4));
  if (stored != computed) {
    error = "wear record checksum mismatch (corrupt)";
    return false;
  }
  ByteReader r(bytes.data(), bytes.size());
  WearRecord w;
  r.u32();
  r.u16();
  if (r.u16() != 0) {
    error = "wear record reserved field is not zero";
    return false;
  }
  if (!text_field_ok(bytes.data() + k_name_offset, k_name_width) ||
      !text_field_ok(bytes.data() + k_name_offset + k_name_width, k_model_width)) {
    error = "wear record name fields are not NUL-terminated printable text";
    return false;
  }
  record_fields(r, w);
  if (!r.ok()) {
    error = "wear record malformed";
    return false;
  }
  bool values_ok = quantity_ok(w.last_friction_coefficient);
  for (size_t k = 0; k < w.bearing.size(); ++k) {
    const AuxBearingWear& b = w.bearing[k];
    for (float v : b.event_load_n) values_ok = values_ok && quantity_ok(v);
    for (float v : b.cumulative_load_n) values_ok = values_ok && quantity_ok(v);
    for (float v : {b.swing_s, b.forward_rub_s, b.backward_rub_s, b.friction_energy_j, b.peak_force_n,
                    b.life_used_fraction})
      values_ok = values_ok && quantity_ok(v);
    if (!values_ok) {
      error = "wear record: a value of aux bearing " + std::to_string(k) +
              " (or the friction coefficient) is negative, infinite or NaN";
      return false;
    }
  }
  out = std::move(w);
  return true;
}

}  // namespace amb::fw
