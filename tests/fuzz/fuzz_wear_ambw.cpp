// AMBW wear records are written back by a host the board does not control: any byte sequence
// is either a valid record (and then re-encodes byte-identically) or refused with a message.
// Each input is tried as it is and with its CRC repaired.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/wear/wear_record.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

void check(const std::vector<uint8_t>& bytes) {
  amb::fw::WearRecord rec;
  std::string error;
  if (!amb::fw::decode_wear_record(bytes, rec, error)) {
    if (error.empty()) __builtin_trap();
    return;
  }
  if (amb::fw::encode_wear_record(rec) != bytes) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> raw(data, data + size);
  check(raw);
  check(amb::fuzz::with_trailing_crc32(raw));
  return 0;
}
