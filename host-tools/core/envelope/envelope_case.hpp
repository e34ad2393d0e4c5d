#pragma once
// One case of a drop-envelope study: the board's drop model (model/drop) levitated at the
// case's speed under its internal controller, then the case's channels cut; its figures are
// the ones the wear record uses (host-tools/core/wear: load map, friction energy, life
// fraction) and the whirl classification of the fit (host-tools/core/fit).
//
// A case is identified by a hash of its canonical key: the study settings and the case
// parameters printed with round-trip precision. Same key -> same result (the drop model is
// deterministic), so a finished case is never run again (restartable studies).
#include <array>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "model/rig/rig_model.hpp"
#include "host-tools/core/envelope/envelope_spec.hpp"

namespace amb::host::envelope {

/// Figures of one simulated drop. Per-bearing arrays are in the board's [[rig.aux_bearing]] order.
struct CaseResult {
  std::array<double, 2> peak_force_n{};        ///< largest step-mean contact force |F| (normal + friction), N
  std::array<std::string, 2> whirl{};          ///< "none", "bouncing", "forward" or "backward" (orbit classification)
  std::array<double, 2> whirl_hz{};            ///< that state's mean |whirl rate|, Hz (0: none)
  std::array<double, 2> friction_energy_j{};   ///< friction work dissipated at the contact, J
  std::array<double, 2> life_fraction{};       ///< life used by this one drop (friction-energy budget), 1
  std::array<double, 2> contact_time_s{};      ///< time with the contact closed, s
  double speed_end_hz = 0.0;                   ///< rotor speed at the end of the window, Hz
  std::uint64_t solver_unconverged = 0;        ///< contact-solver steps that hit the sweep cap (quality flag)
  double wall_s = 0.0;                         ///< wall time of the simulation, s (not part of the result's identity)

  double peak_force_max_n() const { return std::max(peak_force_n[0], peak_force_n[1]); }
  double life_fraction_max() const { return std::max(life_fraction[0], life_fraction[1]); }
  double friction_energy_total_j() const { return friction_energy_j[0] + friction_energy_j[1]; }
  /// The worse whirl of the two bearings (backward > forward > bouncing > none).
  std::string whirl_worst() const;
};

/// Canonical key of a case under `settings` (text; what the hash is taken of).
std::string case_key(const StudySettings& settings, const CaseParams& c);
/// 16 hex digits of the FNV-1a 64-bit hash of case_key().
std::string case_hash(const StudySettings& settings, const CaseParams& c);

/// Simulate one case on `board` (loaded once by the caller; read only, so cases can run
/// in parallel). Throws std::invalid_argument for parameters the board cannot take (e.g. an
/// offset beyond the clearance).
CaseResult run_case(const board::BoardConfig& board, const StudySettings& settings, const CaseParams& c);
/// The same on the board's rig model, built once by the caller and shared by every case.
CaseResult run_case(const board::BoardConfig& board, const std::shared_ptr<const model::RigModel>& rig_model,
                    const StudySettings& settings, const CaseParams& c);

/// JSON of a case file (key, parameters, result) and back. from_case_json throws
/// std::invalid_argument naming the missing or mistyped field.
nlohmann::json to_case_json(const StudySettings& settings, const CaseParams& c, const CaseResult& r);
CaseResult from_case_json(const nlohmann::json& j);
nlohmann::json params_json(const CaseParams& c);

/// Ranking of whirl names (none 0 .. backward 3).
int whirl_rank(const std::string& w);

}  // namespace amb::host::envelope
