#pragma once
// The fit result's JSON (`amb-host fit --json`, format "amb-fit-result/1"): written and read
// back here, and nowhere else. The fleet store recognises and reads fit results through this
// module. Key names and units: docs/drop-model.md ("The fit result's JSON").
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/core/fit/drop_fit.hpp"

namespace amb::host::fit {

/// Value of the "format" key of every fit result written.
inline constexpr const char* k_fit_result_format = "amb-fit-result/1";

/// A fit result as a document: the result and where it came from.
struct FitResultDocument {
  std::string board;      ///< board name the fit ran with ("" unknown: not written)
  std::string event;      ///< the fitted event as given (path), "" unknown: not written
  std::string wear_note;  ///< what was done with the wear record ("" none: not written)
  /// Every field of DropFitResult the JSON carries (not the trace, the free-fall estimate's
  /// state change, nor the friction windows' length_s / force impulse).
  DropFitResult result;
};

/// The JSON object of `doc`.
nlohmann::json fit_result_json(const FitResultDocument& doc);

/// True when `j` is a fit result: format "amb-fit-result/1", or (files written before the
/// format key) an object with a numeric "friction_coefficient" and no "effects_added" (the
/// residual result's key).
bool is_fit_result_json(const nlohmann::json& j);

/// Reads a fit result back. Keys absent are left at their defaults (older or trimmed
/// documents); a key present with the wrong type, a "format" other than this one, or a
/// missing "friction_coefficient" throws std::invalid_argument naming the key.
FitResultDocument read_fit_result_json(const nlohmann::json& j);

}  // namespace amb::host::fit
