// The A/B generation store and the wear store on top of it read whatever a power loss left
// on the storage. The input is split (at a place chosen by its first byte) into the two slot
// files; slot A gets consistent container checksums so the fuzzer reaches the wear record
// inside, slot B stays raw. open() must pick a valid generation or none, never crash, and a
// following store() must make the new payload the newest readable generation.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "firmware/persistence/generation_store.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "hal/sim/sim_rig.hpp"
#include "tests/fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const size_t split = 1 + (static_cast<size_t>(data[0]) * (size - 1)) / 255;  // data[0] places the cut
  const auto a = amb::fuzz::with_container_checksums(std::span<const uint8_t>(data + 1, split - 1));
  const std::vector<uint8_t> b(data + split, data + size);

  {  // the container decoder on its own
    uint64_t generation = 0;
    std::vector<uint8_t> payload;
    std::string error;
    if (!amb::fw::GenerationStore::decode(b, generation, payload, error) && error.empty()) __builtin_trap();
  }
  amb::hal::sim::MemoryStorage storage(1u << 20);
  std::string error;
  storage.write_atomic("wear.a", a, error);
  storage.write_atomic("wear.b", b, error);
  {  // the wear store decodes the AMBW payload of the newest valid generation
    amb::fw::WearStore wear(storage, "bath-amb-rig");
    const auto report = wear.open();
    if (report.found && report.slot < 0) __builtin_trap();
  }
  amb::fw::GenerationStore store(storage, "wear");
  std::vector<uint8_t> payload;
  const auto report = store.open(payload);
  if (report.found && report.slot < 0) __builtin_trap();

  const std::vector<uint8_t> next{1, 2, 3, 4, 5};
  if (!store.store(next, error)) return 0;
  amb::fw::GenerationStore reopened(storage, "wear");
  std::vector<uint8_t> got;
  const auto r2 = reopened.open(got);
  if (!r2.found || got != next) __builtin_trap();
  return 0;
}
