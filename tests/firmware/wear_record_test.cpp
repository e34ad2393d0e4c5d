// AMBW decoding is strict: a record written back by a host must be exactly what the encoder
// would write. Each case below decoded before the fuzzer (scripts/fuzz.sh, fuzz_wear_ambw)
// found that such records did not re-encode to the same bytes; now each is refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "firmware/common/crc32.hpp"
#include "firmware/wear/wear_record.hpp"

namespace {

amb::fw::WearRecord sample_record() {
  amb::fw::WearRecord w;
  w.sequence = 4;
  w.board_name = "bath-amb-rig";
  w.life_model = "friction-energy";
  w.event_count = 2;
  w.last_friction_coefficient = 0.15f;
  w.bearing[0].event_load_n[90] = 250.0f;
  w.bearing[1].life_used_fraction = 0.002f;
  return w;
}

// Re-seal a modified record with a valid CRC so only the field under test is wrong.
void reseal(std::vector<uint8_t>& b) {
  const uint32_t c = amb::fw::crc32(std::span<const uint8_t>(b.data(), b.size() - 4));
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + static_cast<size_t>(i)] = static_cast<uint8_t>(c >> (8 * i));
}

std::string refusal(std::vector<uint8_t> b) {
  reseal(b);
  amb::fw::WearRecord out;
  std::string error;
  EXPECT_FALSE(amb::fw::decode_wear_record(b, out, error));
  return error;
}

constexpr size_t k_name_at = 12, k_model_at = 44, k_friction_at = 112;
// First bearing's life fraction: after the 124-byte header, 2 x 360 loads and 5 other floats.
constexpr size_t k_life0_at = 124 + 4 * (720 + 5);

}  // namespace

TEST(WearRecordDecode, ValidRecordRoundTripsByteForByte) {
  const auto bytes = amb::fw::encode_wear_record(sample_record());
  amb::fw::WearRecord out;
  std::string error;
  ASSERT_TRUE(amb::fw::decode_wear_record(bytes, out, error)) << error;
  EXPECT_EQ(amb::fw::encode_wear_record(out), bytes);
  EXPECT_EQ(out.board_name, "bath-amb-rig");
  // The fixed size the register map announces is what the encoder writes, for any record.
  EXPECT_EQ(bytes.size(), amb::fw::wear_record_size());
  EXPECT_EQ(amb::fw::encode_wear_record(amb::fw::WearRecord{}).size(), amb::fw::wear_record_size());
}

TEST(WearRecordDecode, RefusesNonZeroReservedField) {
  auto b = amb::fw::encode_wear_record(sample_record());
  b[6] = 1;
  EXPECT_NE(refusal(b).find("reserved"), std::string::npos);
}

TEST(WearRecordDecode, RefusesBytesAfterTheNameTerminator) {
  auto b = amb::fw::encode_wear_record(sample_record());
  b[k_name_at + 20] = 'x';  // "bath-amb-rig\0....x..."
  EXPECT_NE(refusal(b).find("name fields"), std::string::npos);
}

TEST(WearRecordDecode, RefusesUnterminatedOrUnprintableNames) {
  auto b = amb::fw::encode_wear_record(sample_record());
  std::memset(b.data() + k_model_at, 'a', 64);
  EXPECT_NE(refusal(b).find("name fields"), std::string::npos);
  b = amb::fw::encode_wear_record(sample_record());
  b[k_name_at + 1] = 0x07;
  EXPECT_NE(refusal(b).find("name fields"), std::string::npos);
}

TEST(WearRecordDecode, RefusesNaNAndNegativeQuantities) {
  ASSERT_EQ(k_life0_at + 4 + 4 * (720 + 6) + 4, amb::fw::wear_record_size());
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), -1.0f, std::numeric_limits<float>::infinity()};
  for (float v : bad) {
    for (size_t at : {k_friction_at, k_life0_at}) {
      auto b = amb::fw::encode_wear_record(sample_record());
      std::memcpy(b.data() + at, &v, 4);
      EXPECT_NE(refusal(b).find("negative, infinite or NaN"), std::string::npos) << "value " << v << " at " << at;
    }
  }
}
