// The AMBE and AMBW codecs against files written by an earlier encoder (tests/firmware/data/,
// written once by the encoder of commit 0e43c0e, the last one with mirrored encode/decode
// lists, before the field tables of event_codec.cpp / wear_record.cpp): every file decodes,
// re-encodes byte for byte, and the record below (every field set to a distinct value, so a
// swapped, dropped or retyped field changes the bytes) encodes to the same bytes.
//
// Regenerating the files is never needed for a format that did not change; a new format
// version gets new files (AMB_WRITE_CODEC_GOLDEN=FOLDER writes them, then review the diff).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "firmware/events/event_codec.hpp"
#include "firmware/wear/wear_record.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fw = amb::fw;

/// A record whose every stored field holds a value of its own (distinct bit patterns). Every
/// value is exact in binary (integers, dyadic fractions): a compiler that fuses a multiply and
/// an add (aarch64) computes the same bits as one that does not.
fw::EventRecord golden_event() {
  fw::EventRecord r;
  auto& m = r.meta;
  m.board_name = "golden-board";
  m.rig_name = "golden-rig";
  m.firmware_version = "amb-firmware 9.8.7";
  m.board_source = "embedded:golden-board";
  m.event_number = 0x0102030405060708ull;
  m.capture_number = 17;
  m.rate_hz = 10000.5;
  m.pre_trigger_s = 0.25;
  m.post_trigger_s = 0.75;
  m.cause = fw::TriggerCause::channel_cutoff;
  m.cutoff_channels = 0x0B;
  m.cause_mask = 0x00A1B2C3;
  m.trigger_index = 1;
  m.seq_gaps = 3;
  m.trigger_seq = 123456789;
  m.trigger_t_ns = -987654321;
  m.speed_at_trigger_hz = 45.125;
  m.first_t_ns = 1000;
  m.last_t_ns = 3000;
  m.events_lost_before = 2;
  m.kp_n_per_m = 1.1e6;
  m.ki_n_per_m_s = 2.2e7;
  m.kd_n_s_per_m = 3.3e3;
  m.derivative_filter_hz = 4400.0;
  m.integrator_limit_n = 550.0;
  m.current_limit_a = 6.6;
  for (size_t k = 0; k < 4; ++k) {
    m.sensors[k] = {0.125 + 0.0625 * static_cast<double>(k), 45.0 - 90.0 * static_cast<double>(k)};
    m.actuators[k] = {0.25 + 0.0625 * static_cast<double>(k), -45.0 + 30.0 * static_cast<double>(k), 100.0 + static_cast<double>(k)};
  }
  m.orbit_trigger_limit_m = 2.5e-4;
  m.current_trigger_limit_a = 7.5;
  for (int i = 0; i < 3; ++i) {
    fw::LoopSample s;
    const float f = static_cast<float>(i);
    s.seq = 100 + static_cast<uint64_t>(i);
    s.t_ns = 1000 + 1000 * i;
    for (size_t k = 0; k < 4; ++k) {
      s.displacement_m[k] = 0x1p-17f * static_cast<float>(4 * i + static_cast<int>(k) + 1);
      s.coil_current_a[k] = 0.5f * f - 0.125f * static_cast<float>(k);
      s.current_demand_a[k] = 0.25f * f + 0.0625f * static_cast<float>(k);
    }
    s.speed_hz = 45.0f - 0.5f * f;
    s.speed_command_hz = 45.0f + f;
    s.state = static_cast<uint8_t>(2 + i);
    s.phase = static_cast<uint8_t>(5 + i);
    s.fault = static_cast<uint8_t>(9 + i);
    s.speed_quality = static_cast<uint8_t>(0x80 | (90 + i));
    s.flags = 0x10000 + static_cast<uint32_t>(i);
    s.tach_hz = 44.75f - f;
    r.samples.push_back(s);
  }
  r.has_diagnosis = true;
  auto& d = r.diagnosis;
  d.type = fw::diag::FaultType::misalignment;
  d.cutoff_channels = 0x05;
  d.disturbance_channels = 0x0A;
  d.misalignment_plane = -1;  // stored as a signed byte
  d.confidence = 0.875;
  d.current_factor = {0.0, 0.5, 1.0, 0.25};
  d.disturbance_frequency_hz = 123.5;
  d.disturbance_amplitude_a = 0.375;
  d.current_lead_s = 1.5e-3;
  d.speed_hz = 44.5;
  d.radius_1x_start_m = {1e-6, 2e-6};
  d.radius_1x_end_m = {3e-6, 4e-6};
  d.centre_shift_m = {5e-6, -6e-6};
  d.misalignment_direction_deg = 210.0;
  d.summary = "golden diagnosis summary";
  r.has_analysis = true;
  auto& a = r.analysis;
  a.speed_source = 2;
  a.speed_lost_at_trigger = true;
  a.quick_look_valid = true;
  a.speed_confidence_at_trigger = 0.625;
  a.quick_look_spin_hz = 12.5;
  a.aux_contact_constant_n_per_m1p5 = 3.5e9;
  a.aux_dynamic_load_rating_n = 7100.0;
  for (size_t b = 0; b < 2; ++b) {
    a.aux[b].valid = b == 0;
    a.aux[b].samples_in_contact = 40 + static_cast<uint32_t>(b);
    a.aux[b].peak_force_n = 1500.0 + 10.0 * static_cast<double>(b);
    a.aux[b].peak_angle_deg = 33.0 + static_cast<double>(b);
    a.aux[b].life_fraction = 1e-4 * static_cast<double>(b + 1);
    a.aux[b].contact_time_s = 0.03125 + 0.015625 * static_cast<double>(b);
  }
  return r;
}

fw::WearRecord golden_wear() {
  fw::WearRecord w;
  w.sequence = 7;
  w.board_name = "golden-board";
  w.life_model = "friction-energy budget (Archard) 20000 J";
  w.event_count = 5;
  w.last_friction_coefficient = 0.1875f;
  w.updated_unix_s = 1800000000;
  for (size_t b = 0; b < 2; ++b) {
    auto& x = w.bearing[b];
    for (size_t i = 0; i < x.event_load_n.size(); ++i) {
      x.event_load_n[i] = static_cast<float>(i) + 0.5f * static_cast<float>(b);
      x.cumulative_load_n[i] = 2.0f * static_cast<float>(i) + 0.25f + static_cast<float>(b);
    }
    x.swing_s = 0.125f + static_cast<float>(b);
    x.forward_rub_s = 0.25f + static_cast<float>(b);
    x.backward_rub_s = 0.375f + static_cast<float>(b);
    x.friction_energy_j = 1500.0f + static_cast<float>(b);
    x.peak_force_n = 4200.0f + static_cast<float>(b);
    x.life_used_fraction = 0.0625f + 0x1p-10f * static_cast<float>(b);
  }
  return w;
}

std::filesystem::path data_dir() { return std::filesystem::path(amb::test::source_dir()) / "tests/firmware/data"; }

std::vector<uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  EXPECT_TRUE(in) << p << " cannot be read";
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& p, const std::vector<uint8_t>& b) {
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

struct EventFile {
  const char* name;
  std::vector<uint8_t> (*encode)(const fw::EventRecord&);
  uint16_t version;
};
const EventFile k_event_files[] = {{"golden_v3.ambe", fw::encode_event, 3},
                                   {"golden_v2.ambe", fw::encode_event_v2, 2},
                                   {"golden_v1.ambe", fw::encode_event_v1, 1}};

// Not a test: writes the golden files where AMB_WRITE_CODEC_GOLDEN points (see the top).
TEST(CodecGolden, WriteWhenAsked) {
  const char* dir = std::getenv("AMB_WRITE_CODEC_GOLDEN");
  if (!dir) GTEST_SKIP() << "AMB_WRITE_CODEC_GOLDEN not set";
  for (const auto& f : k_event_files) write_bytes(std::filesystem::path(dir) / f.name, f.encode(golden_event()));
  fw::EventRecord no_diag = golden_event();
  no_diag.has_diagnosis = false;
  write_bytes(std::filesystem::path(dir) / "golden_nodiag_v3.ambe", fw::encode_event(no_diag));
  write_bytes(std::filesystem::path(dir) / "golden.ambw", fw::encode_wear_record(golden_wear()));
}

TEST(CodecGolden, EventFilesDecodeAndReencodeByteIdentical) {
  for (const auto& f : k_event_files) {
    SCOPED_TRACE(f.name);
    const auto bytes = read_bytes(data_dir() / f.name);
    ASSERT_FALSE(bytes.empty());
    fw::EventRecord r;
    std::string err;
    ASSERT_TRUE(fw::decode_event(bytes, r, err)) << err;
    EXPECT_EQ(r.format_version, f.version);
    EXPECT_EQ(f.encode(r), bytes);
    // The record as written then: the encoder of today gives the same bytes.
    EXPECT_EQ(f.encode(golden_event()), bytes);
  }
  const auto bytes = read_bytes(data_dir() / "golden_nodiag_v3.ambe");
  fw::EventRecord r;
  std::string err;
  ASSERT_TRUE(fw::decode_event(bytes, r, err)) << err;
  EXPECT_FALSE(r.has_diagnosis);
  EXPECT_EQ(fw::encode_event(r), bytes);
}

TEST(CodecGolden, EventFieldsReadBackAsWritten) {
  const auto bytes = read_bytes(data_dir() / "golden_v3.ambe");
  fw::EventRecord r;
  std::string err;
  ASSERT_TRUE(fw::decode_event(bytes, r, err)) << err;
  const fw::EventRecord g = golden_event();
  EXPECT_EQ(r.meta.board_source, g.meta.board_source);
  EXPECT_EQ(r.meta.event_number, g.meta.event_number);
  EXPECT_EQ(r.meta.cause, g.meta.cause);
  EXPECT_EQ(r.meta.trigger_t_ns, g.meta.trigger_t_ns);
  EXPECT_EQ(r.meta.actuators[3].ki_n_per_a, g.meta.actuators[3].ki_n_per_a);
  EXPECT_EQ(r.meta.current_trigger_limit_a, g.meta.current_trigger_limit_a);
  ASSERT_EQ(r.samples.size(), g.samples.size());
  EXPECT_EQ(r.samples[2].tach_hz, g.samples[2].tach_hz);
  EXPECT_EQ(r.samples[2].flags, g.samples[2].flags);
  EXPECT_EQ(r.samples[1].current_demand_a[3], g.samples[1].current_demand_a[3]);
  EXPECT_EQ(r.diagnosis.misalignment_plane, -1);
  EXPECT_EQ(r.diagnosis.summary, g.diagnosis.summary);
  EXPECT_EQ(r.diagnosis.centre_shift_m[1], g.diagnosis.centre_shift_m[1]);
  EXPECT_TRUE(r.analysis.speed_lost_at_trigger);
  EXPECT_FALSE(r.analysis.aux[1].valid);
  EXPECT_EQ(r.analysis.aux[1].contact_time_s, g.analysis.aux[1].contact_time_s);
  // Version 1 and 2 files carry no tachometer channel: read as -1 (none).
  ASSERT_TRUE(fw::decode_event(read_bytes(data_dir() / "golden_v2.ambe"), r, err)) << err;
  EXPECT_EQ(r.samples[0].tach_hz, -1.0f);
}

TEST(CodecGolden, WearRecordDecodesAndReencodesByteIdentical) {
  const auto bytes = read_bytes(data_dir() / "golden.ambw");
  fw::WearRecord w;
  std::string err;
  ASSERT_TRUE(fw::decode_wear_record(bytes, w, err)) << err;
  EXPECT_EQ(fw::encode_wear_record(w), bytes);
  EXPECT_EQ(fw::encode_wear_record(golden_wear()), bytes);
  const fw::WearRecord g = golden_wear();
  EXPECT_EQ(w.life_model, g.life_model);
  EXPECT_EQ(w.updated_unix_s, g.updated_unix_s);
  EXPECT_EQ(w.bearing[1].cumulative_load_n[359], g.bearing[1].cumulative_load_n[359]);
  EXPECT_EQ(w.bearing[1].life_used_fraction, g.bearing[1].life_used_fraction);
}

}  // namespace
