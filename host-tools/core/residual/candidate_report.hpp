#pragma once
// How every record kind reports its candidates: the evidence, the criterion's value and its
// threshold, kept or rejected with the reason, and the features before and after (one writer
// for the JSON and one for the text, so the four record kinds report alike).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/core/residual/residual_loop.hpp"

namespace amb::host::residual {

/// {name, testable, delta_bic, evidence, decided, kept, criterion: {value, threshold}, reason,
///  decision_features: [{name, unit, before, after}], information_features: [...]}
nlohmann::json candidate_json(const CandidateScore& c);
nlohmann::json candidates_json(const std::vector<CandidateScore>& v);

/// One line per candidate: "name: kept|rejected (dIC v vs t): reason; evidence".
std::string candidate_text(const CandidateScore& c);

}  // namespace amb::host::residual
