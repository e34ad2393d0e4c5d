#pragma once
// The auxiliary-bearing wear record (seed 000 Phase E): the load over each bearing's
// circumference, event count, rubbing-state durations, dissipated friction energy and a
// life estimate. Computed on the host, written back to the board, persisted there.
// Binary format `AMBW` version 1, little-endian, CRC-32 over everything before the CRC.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace amb::fw {

inline constexpr int k_load_bins = 360;  ///< 1-degree polar bins, 0 deg = upward vertical, towards +x

struct AuxBearingWear {
  std::array<float, k_load_bins> event_load_n{};       ///< sum of contact forces per bin, last event, N
  std::array<float, k_load_bins> cumulative_load_n{};  ///< same, all events, N
  float swing_s = 0.0f;            ///< cumulative time in swinging (bouncing) contact, s
  float forward_rub_s = 0.0f;      ///< cumulative forward rub (whirl with the spin), s
  float backward_rub_s = 0.0f;     ///< cumulative backward whirl, s
  float friction_energy_j = 0.0f;  ///< cumulative friction energy dissipated, J
  float peak_force_n = 0.0f;       ///< largest contact force seen, N
  float life_used_fraction = 0.0f; ///< consumed fraction of the estimated life (model: life_model)
};

struct WearRecord {
  static constexpr uint32_t k_magic = 0x57424D41u;  ///< "AMBW"
  static constexpr uint16_t k_version = 1;
  uint32_t sequence = 0;           ///< increases by one with each accepted write-back
  std::string board_name;          ///< board the record belongs to (max 31 chars)
  std::string life_model;          ///< name of the life model used (max 63 chars)
  uint32_t event_count = 0;        ///< drop events accounted for
  float last_friction_coefficient = 0.0f;  ///< from the last fit
  int64_t updated_unix_s = 0;      ///< when the host computed it (host wall clock), s
  std::array<AuxBearingWear, 2> bearing{};
};

/// Encode (with CRC). Not real-time.
std::vector<uint8_t> encode_wear_record(const WearRecord& r);

/// Decode and validate magic, version, size and CRC. On failure returns false and says
/// what is wrong in `error`; `out` is untouched.
bool decode_wear_record(const std::vector<uint8_t>& bytes, WearRecord& out, std::string& error);

/// Size of an encoded record, bytes (fixed: header 124, per bearing two maps of k_load_bins
/// floats and six floats, CRC 4).
constexpr size_t wear_record_size() {
  return 4 + 2 + 2 + 4 + 32 + 64 + 4 + 4 + 8 + 2 * (2 * static_cast<size_t>(k_load_bins) + 6) * 4 + 4;
}

}  // namespace amb::fw
