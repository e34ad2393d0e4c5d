#include "firmware/persistence/generation_store.hpp"

#include <limits>

#include "firmware/common/byte_codec.hpp"
#include "firmware/persistence/crc32c.hpp"

namespace amb::fw {

namespace {
constexpr uint32_t k_magic = 0x47424D41u;  // "AMBG"
constexpr uint16_t k_version = 1;
constexpr size_t k_header_bytes = k_generation_header_bytes;
constexpr uint32_t k_max_payload = 64u << 20;
}  // namespace

GenerationStore::GenerationStore(hal::Storage& storage, std::string base_name)
    : storage_(storage), names_{base_name + ".a", base_name + ".b"} {}

std::vector<uint8_t> GenerationStore::encode(uint64_t generation, std::span<const uint8_t> payload) {
  std::vector<uint8_t> out;
  out.reserve(k_header_bytes + payload.size());
  ByteWriter w(out);
  w.u32(k_magic);
  w.u16(k_version);
  w.u16(0);
  w.u64(generation);
  w.u32(static_cast<uint32_t>(payload.size()));
  w.u32(crc32c(payload));
  w.u32(crc32c(std::span<const uint8_t>(out.data(), out.size())));
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

bool GenerationStore::decode(const std::vector<uint8_t>& bytes, uint64_t& generation, std::vector<uint8_t>& payload,
                             std::string& error) {
  if (bytes.size() < k_header_bytes) {
    error = "torn (" + std::to_string(bytes.size()) + " bytes, header needs " + std::to_string(k_header_bytes) + ")";
    return false;
  }
  ByteReader r(bytes.data(), bytes.size());
  const uint32_t magic = r.u32();
  const uint16_t version = r.u16();
  r.u16();
  const uint64_t gen = r.u64();
  const uint32_t size = r.u32();
  const uint32_t payload_crc = r.u32();
  const uint32_t header_crc = r.u32();
  if (magic != k_magic) {
    error = "bad magic";
    return false;
  }
  if (header_crc != crc32c(std::span<const uint8_t>(bytes.data(), k_header_bytes - 4))) {
    error = "header checksum mismatch";
    return false;
  }
  if (version != k_version) {
    error = "container version " + std::to_string(version) + " not supported";
    return false;
  }
  if (size > k_max_payload || bytes.size() != k_header_bytes + size) {
    error = "size mismatch (" + std::to_string(bytes.size() - k_header_bytes) + " payload bytes, header says " +
            std::to_string(size) + ")";
    return false;
  }
  const std::span<const uint8_t> p(bytes.data() + k_header_bytes, size);
  if (crc32c(p) != payload_crc) {
    error = "payload checksum mismatch";
    return false;
  }
  generation = gen;
  payload.assign(p.begin(), p.end());
  return true;
}

GenerationReport GenerationStore::open(std::vector<uint8_t>& payload) {
  GenerationReport rep;
  payload.clear();
  generation_ = 0;
  newest_slot_ = -1;
  const auto names = storage_.list();
  for (int s = 0; s < 2; ++s) {
    const std::string& name = names_[static_cast<size_t>(s)];
    bool present = false;
    for (const auto& n : names) present = present || n == name;
    if (!present) {
      rep.detail += name + ": absent; ";
      continue;
    }
    std::vector<uint8_t> bytes, p;
    std::string err;
    uint64_t gen = 0;
    if (!storage_.read(name, bytes, err) || !decode(bytes, gen, p, err)) {
      ++rep.corrupt_slots;
      rep.detail += name + ": " + err + "; ";
      continue;
    }
    rep.detail += name + ": generation " + std::to_string(gen) + "; ";
    if (newest_slot_ < 0 || gen > generation_) {
      generation_ = gen;
      newest_slot_ = s;
      payload = std::move(p);
    }
  }
  rep.found = newest_slot_ >= 0;
  rep.generation = generation_;
  rep.slot = newest_slot_;
  return rep;
}

bool GenerationStore::store(std::span<const uint8_t> payload, std::string& error) {
  const int target = newest_slot_ == 0 ? 1 : 0;
  // A slot may carry any generation number (found by fuzzing: a stored generation of 2^64-1
  // made the next one wrap to 0, older than the record it replaced, so it was lost at the
  // next open). Refuse instead of wrapping; the previous record stays the newest.
  if (generation_ == std::numeric_limits<uint64_t>::max()) {
    error = "generation counter exhausted (newest generation is 2^64-1)";
    return false;
  }
  const uint64_t gen = generation_ + 1;
  const auto bytes = encode(gen, payload);
  if (!storage_.write_atomic(names_[static_cast<size_t>(target)], bytes, error)) return false;
  generation_ = gen;
  newest_slot_ = target;
  return true;
}

}  // namespace amb::fw
