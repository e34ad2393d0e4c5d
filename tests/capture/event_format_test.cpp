// AMBE event files (v3, and v1/v2 still read): round trip, refusal of truncated / corrupted / wrong-version files
// with a message saying what is wrong, and the event store's full-storage policy.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "firmware/board/board.hpp"
#include "firmware/common/crc32.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/event_store.hpp"
#include "hal/sim/sim_rig.hpp"
#include "tests/capture/synthetic_samples.hpp"

namespace {
using namespace amb::fw;

EventRecord sample_record(size_t n = 300, bool with_diag = true) {
  const auto board = amb::board::load_board("bath-amb-rig");
  FrozenEvent e;
  e.samples.resize(n);
  for (size_t i = 0; i < n; ++i) e.samples[i] = amb::test::synthetic_sample(1000 + i);
  e.header.sample_count = static_cast<uint32_t>(n);
  e.header.trigger_index = 100;
  e.header.trigger_seq = 1100;
  e.header.cause = TriggerCause::orbit_radius;
  e.header.cause_mask = cause_bit(TriggerCause::orbit_radius) | cause_bit(TriggerCause::current_limit);
  e.header.speed_at_trigger_hz = 45.0f;
  EventRecord r = make_event_record(e, board, 7);
  if (with_diag) {
    r.has_diagnosis = true;
    r.diagnosis.type = diag::FaultType::misalignment;
    r.diagnosis.confidence = 0.8;
    r.diagnosis.misalignment_direction_deg = 30.0;
    r.diagnosis.misalignment_plane = 1;
    r.diagnosis.summary = "misalignment towards 30 deg";
  }
  r.has_analysis = true;
  r.analysis.speed_source = 1;
  r.analysis.speed_confidence_at_trigger = 0.87;
  r.analysis.quick_look_valid = true;
  r.analysis.quick_look_spin_hz = 45.0;
  r.analysis.aux[1] = {true, 1234, 812.5, 271.0, 3.5e-7, 0.1234};
  return r;
}

// A tachometer channel on the samples (v3): seq-dependent speeds, one sample invalid (NaN).
EventRecord with_tach(EventRecord r) {
  for (auto& s : r.samples) s.tach_hz = 45.0f - 0.01f * static_cast<float>(s.seq % 1000);
  r.samples[17].tach_hz = std::numeric_limits<float>::quiet_NaN();
  return r;
}

TEST(EventFormat, RoundTripKeepsEverything) {
  const EventRecord r = with_tach(sample_record());
  const auto bytes = encode_event(r);
  EXPECT_EQ(bytes[4], 3);
  EXPECT_EQ(bytes.size(), k_event_preamble_bytes + k_event_meta_bytes_v1 + 300 * k_event_sample_bytes_v3 +
                              k_event_diagnosis_bytes_v1 + k_event_analysis_bytes_v2 + 4);
  EventRecord back;
  std::string err;
  ASSERT_TRUE(decode_event(bytes, back, err)) << err;
  EXPECT_EQ(back.meta.board_name, "bath-amb-rig");
  EXPECT_EQ(back.meta.rig_name, "bath-amb-rig");
  EXPECT_EQ(back.meta.firmware_version, k_firmware_version);
  EXPECT_EQ(back.meta.event_number, 7u);
  EXPECT_EQ(back.meta.rate_hz, 10000.0);
  EXPECT_EQ(back.meta.cause, TriggerCause::orbit_radius);
  EXPECT_EQ(back.meta.cause_mask, r.meta.cause_mask);
  EXPECT_EQ(back.meta.trigger_index, 100u);
  EXPECT_EQ(back.meta.kp_n_per_m, r.meta.kp_n_per_m);
  EXPECT_EQ(back.meta.sensors[3].angle_deg, -45.0);
  EXPECT_EQ(back.meta.sensors[2].axial_m, r.meta.sensors[2].axial_m);
  EXPECT_EQ(back.meta.actuators[1].angle_deg, -45.0);
  EXPECT_EQ(back.meta.orbit_trigger_limit_m, 0.2e-3);
  ASSERT_EQ(back.samples.size(), 300u);
  EXPECT_EQ(back.format_version, 3);
  for (size_t i = 0; i < 300; ++i) {
    EXPECT_EQ(back.samples[i].seq, 1000 + i);
    LoopSample s = back.samples[i];
    if (i == 17) {
      EXPECT_TRUE(std::isnan(s.tach_hz));
    } else {
      EXPECT_EQ(s.tach_hz, r.samples[i].tach_hz) << i;
    }
    s.tach_hz = -1.0f;  // the rest as synthetic_sample made it
    EXPECT_TRUE(amb::test::is_intact(s));
  }
  ASSERT_TRUE(back.has_diagnosis);
  EXPECT_EQ(back.diagnosis.type, diag::FaultType::misalignment);
  EXPECT_EQ(back.diagnosis.misalignment_plane, 1);
  EXPECT_EQ(back.diagnosis.summary, "misalignment towards 30 deg");
  ASSERT_TRUE(back.has_analysis);
  EXPECT_EQ(back.analysis.speed_source, r.analysis.speed_source);
  EXPECT_EQ(back.analysis.speed_confidence_at_trigger, r.analysis.speed_confidence_at_trigger);
  EXPECT_EQ(back.analysis.speed_lost_at_trigger, r.analysis.speed_lost_at_trigger);
  EXPECT_EQ(back.analysis.quick_look_valid, r.analysis.quick_look_valid);
  for (size_t b = 0; b < 2; ++b) {
    EXPECT_EQ(back.analysis.aux[b].peak_force_n, r.analysis.aux[b].peak_force_n);
    EXPECT_EQ(back.analysis.aux[b].peak_angle_deg, r.analysis.aux[b].peak_angle_deg);
    EXPECT_EQ(back.analysis.aux[b].life_fraction, r.analysis.aux[b].life_fraction);
    EXPECT_EQ(back.analysis.aux[b].samples_in_contact, r.analysis.aux[b].samples_in_contact);
  }
}

// Files written before the analysis section (AMBE v1) are still read, without one.
TEST(EventFormat, Version1FilesAreStillRead) {
  const EventRecord r = with_tach(sample_record());
  const auto bytes = encode_event_v1(r);
  EXPECT_EQ(bytes[4], 1);
  EXPECT_EQ(bytes.size(), k_event_preamble_bytes + k_event_meta_bytes_v1 + 300 * k_event_sample_bytes_v1 +
                              k_event_diagnosis_bytes_v1 + 4);
  EventRecord back;
  std::string err;
  ASSERT_TRUE(decode_event(bytes, back, err)) << err;
  EXPECT_FALSE(back.has_analysis);
  EXPECT_EQ(back.format_version, 1);
  ASSERT_EQ(back.samples.size(), 300u);
  EXPECT_TRUE(amb::test::is_intact(back.samples[299]));  // tach_hz -1: no tachometer channel in v1
  ASSERT_TRUE(back.has_diagnosis);
  EXPECT_EQ(back.diagnosis.summary, "misalignment towards 30 deg");
}

// Files written before the tachometer channel (AMBE v2, 80-byte samples) are still read: the
// analysis section is there, every sample says "no tachometer" (tach_hz -1).
TEST(EventFormat, Version2FilesAreStillReadWithoutTachometer) {
  const EventRecord r = with_tach(sample_record());
  const auto bytes = encode_event_v2(r);
  EXPECT_EQ(bytes[4], 2);
  EXPECT_EQ(bytes.size(), k_event_preamble_bytes + k_event_meta_bytes_v1 + 300 * k_event_sample_bytes_v1 +
                              k_event_diagnosis_bytes_v1 + k_event_analysis_bytes_v2 + 4);
  EventRecord back;
  std::string err;
  ASSERT_TRUE(decode_event(bytes, back, err)) << err;
  EXPECT_EQ(back.format_version, 2);
  ASSERT_TRUE(back.has_analysis);
  EXPECT_EQ(back.analysis.speed_confidence_at_trigger, r.analysis.speed_confidence_at_trigger);
  ASSERT_EQ(back.samples.size(), 300u);
  for (size_t i = 0; i < 300; ++i) EXPECT_TRUE(amb::test::is_intact(back.samples[i])) << i;
  // A v2 header with v3-sized samples (or the reverse) does not add up: refused, not misread.
  auto v3 = encode_event(r);
  v3[4] = 2;
  const uint32_t crc = crc32(std::span(v3).first(v3.size() - 4));
  for (int i = 0; i < 4; ++i) v3[v3.size() - 4 + static_cast<size_t>(i)] = static_cast<uint8_t>(crc >> (8 * i));
  EXPECT_FALSE(decode_event(v3, back, err));
  EXPECT_NE(err.find("inconsistent sizes"), std::string::npos) << err;
}

TEST(EventFormat, TableCrcMatchesABitwiseCrcAndTheCheckValue) {
  const auto bytes = encode_event(sample_record(50));
  uint32_t bitwise = ~0u;  // the polynomial division one bit at a time
  for (uint8_t b : bytes) {
    bitwise ^= b;
    for (int k = 0; k < 8; ++k) bitwise = (bitwise >> 1) ^ (0xEDB88320u & (0u - (bitwise & 1u)));
  }
  EXPECT_EQ(crc32(bytes), ~bitwise);
  // Continuing over a split gives the same value.
  EXPECT_EQ(crc32(std::span(bytes).subspan(1000), crc32(std::span(bytes).first(1000))), ~bitwise);
  const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(crc32(check), 0xCBF43926u);  // the standard CRC-32 check value
}

TEST(EventFormat, TruncatedFileIsRefusedAsTruncated) {
  const auto bytes = encode_event(sample_record());
  for (size_t keep : {size_t{0}, size_t{10}, size_t{31}, size_t{500}, bytes.size() - 1}) {
    EventRecord out;
    std::string err;
    EXPECT_FALSE(decode_event(std::span(bytes).first(keep), out, err)) << keep;
    EXPECT_NE(err.find("truncated"), std::string::npos) << keep << ": " << err;
  }
}

TEST(EventFormat, CorruptedByteIsRefusedAsBadChecksum) {
  auto bytes = encode_event(sample_record());
  for (size_t at : {size_t{40}, size_t{5000}, bytes.size() - 100, bytes.size() - 2}) {
    auto bad = bytes;
    bad[at] ^= 0x10;
    EventRecord out;
    std::string err;
    EXPECT_FALSE(decode_event(bad, out, err));
    EXPECT_NE(err.find("bad checksum"), std::string::npos) << at << ": " << err;
  }
}

TEST(EventFormat, WrongVersionIsRefusedAsSuch) {
  auto bytes = encode_event(sample_record());
  bytes[4] = 5;  // version 5 (newer than this reader: 4 is the sweep-event version), with a valid checksum
  const uint32_t crc = crc32(std::span(bytes).first(bytes.size() - 4));
  for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + static_cast<size_t>(i)] = static_cast<uint8_t>(crc >> (8 * i));
  EventRecord out;
  std::string err;
  EXPECT_FALSE(decode_event(bytes, out, err));
  EXPECT_NE(err.find("unsupported version 5"), std::string::npos) << err;
}

TEST(EventFormat, NotAnEventFile) {
  std::vector<uint8_t> bytes(100, 'x');
  EventRecord out;
  std::string err;
  EXPECT_FALSE(decode_event(bytes, out, err));
  EXPECT_NE(err.find("not an AMBE event file"), std::string::npos) << err;
}

TEST(EventStore, DropOldestNeverTheNewestAndSkipsProtected) {
  amb::hal::sim::MemoryStorage storage(1 << 20);
  CaptureParams p;
  p.max_events = 3;
  p.storage_policy = StoragePolicy::drop_oldest;
  EventStore store(storage, p);
  const std::vector<uint8_t> blob(1000, 1);
  std::string err;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(store.store(store.next_number(), blob, err)) << err;
  store.set_protected(1, true);
  ASSERT_TRUE(store.store(store.next_number(), blob, err)) << err;  // drops 2 (1 is protected)
  EXPECT_EQ(store.numbers(), (std::vector<uint64_t>{1, 3, 4}));
  EXPECT_EQ(store.counters().dropped_oldest, 1u);
  // A store re-opened on the same storage continues the numbering.
  EventStore again(storage, p);
  EXPECT_EQ(again.next_number(), 5u);
  EXPECT_EQ(again.numbers(), (std::vector<uint64_t>{1, 3, 4}));
}

TEST(EventStore, RefuseNewKeepsOldAndCounts) {
  amb::hal::sim::MemoryStorage storage(1 << 20);
  CaptureParams p;
  p.max_events = 2;
  p.storage_policy = StoragePolicy::refuse_new;
  EventStore store(storage, p);
  const std::vector<uint8_t> blob(1000, 1);
  std::string err;
  ASSERT_TRUE(store.store(store.next_number(), blob, err));
  ASSERT_TRUE(store.store(store.next_number(), blob, err));
  EXPECT_FALSE(store.store(store.next_number(), blob, err));
  EXPECT_NE(err.find("refuse_new"), std::string::npos) << err;
  EXPECT_EQ(store.counters().refused, 1u);
  EXPECT_EQ(storage.list().size(), 2u);
}

TEST(EventStore, StorageSmallerThanTheBudgetIsRespected) {
  amb::hal::sim::MemoryStorage storage(2500);  // room for two 1000-byte events
  CaptureParams p;
  EventStore store(storage, p);
  const std::vector<uint8_t> blob(1000, 1);
  std::string err;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(store.store(store.next_number(), blob, err)) << err;
  EXPECT_EQ(store.numbers(), (std::vector<uint64_t>{4, 5}));
  // An event larger than the whole storage is not stored (a storage fault: the event writer
  // retries it, counted), nothing is dropped for it, and nothing is left half-written.
  const std::vector<uint8_t> big(4000, 2);
  EXPECT_EQ(store.put(store.next_number(), big, err), StoreResult::failed);
  EXPECT_EQ(store.counters().no_space, 1u);
  EXPECT_EQ(store.numbers(), (std::vector<uint64_t>{4, 5}));
  for (const auto& name : storage.list()) {
    std::vector<uint8_t> b;
    ASSERT_TRUE(storage.read(name, b, err));
    EXPECT_EQ(b.size(), 1000u);
  }
}

}  // namespace
