#pragma once
// SHA-256 (FIPS 180-4) of a byte string: the fleet store's content hash (an event, wear
// record or result file imported twice is recognised by it).
#include <cstdint>
#include <span>
#include <string>

namespace amb::host::fleet {

/// 64 lower-case hex digits.
std::string sha256_hex(std::span<const std::uint8_t> data);

}  // namespace amb::host::fleet
