// AMBE event files arrive over Modbus downloads and from disk: the decoders (drop events, and
// sweep events: AMBE v4 record kind sweep) must refuse any malformed byte sequence with a
// message, and what they accept must re-encode to a file that decodes again (round trip). Each
// input is tried as it is and with its CRC repaired.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "firmware/events/event_codec.hpp"
#include "firmware/events/sweep_event.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

void check(std::span<const uint8_t> bytes) {
  amb::fw::EventRecord rec;
  std::string error;
  if (!amb::fw::decode_event(bytes, rec, error)) {
    if (error.empty()) __builtin_trap();  // a refusal must say why
    return;
  }
  const auto again = amb::fw::encode_event(rec);
  amb::fw::EventRecord rec2;
  if (!amb::fw::decode_event(again, rec2, error)) __builtin_trap();
}

void check_sweep(std::span<const uint8_t> bytes) {
  amb::fw::SweepEvent ev;
  std::string error;
  if (!amb::fw::decode_sweep_event(bytes, ev, error)) {
    if (error.empty()) __builtin_trap();
    return;
  }
  const auto again = amb::fw::encode_sweep_event(ev);
  if (again.size() != bytes.size()) __builtin_trap();  // the layout is fixed by the counts
  amb::fw::SweepEvent ev2;
  if (!amb::fw::decode_sweep_event(again, ev2, error)) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const uint8_t> in(data, size);
  check(in);
  check_sweep(in);
  const auto repaired = amb::fuzz::with_trailing_crc32(in);
  check(repaired);
  check_sweep(repaired);
  return 0;
}
