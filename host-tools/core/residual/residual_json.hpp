#pragma once
// The residual loop's results as the command prints them: one JSON document and one text
// block per record kind (steady run, drop event, sweep), written here so that tests reach
// them and the command only parses options (amb-host residual: host-tools/amb-host/cmd_residual.cpp).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/learned_correction.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/residual/sweep_frf.hpp"

namespace amb::host::residual {

/// Error figures {rms, spectral, pearson, statics}.
nlohmann::json error_figures_json(const ErrorFigures& e);
/// The elements added, with parameters, evidence and BIC decrease.
nlohmann::json effects_added_json(const std::vector<EffectAdded>& v);
/// Unexplained residual features: what, where, how large against the noise.
nlohmann::json unexplained_json(const std::vector<UnexplainedItem>& v);
/// The learned correction (reported apart from the named elements; key "learned_correction").
nlohmann::json learned_correction_json(const LearnedCorrectionSummary& s);

/// Whole documents of `amb-host residual --json`, per record kind.
nlohmann::json steady_residual_json(const SteadyData& d, const ResidualOutcome& o);
/// `notes` and `ranking`: the levitated part's and the drop part's together (drop_notes_and_ranking).
nlohmann::json drop_residual_json(const DropResidualOutcome& o);
nlohmann::json sweep_residual_json(const SweepOutcome& o);

/// The structure notes and the candidate ranking of a drop event: levitated part first.
std::vector<std::string> drop_notes(const DropResidualOutcome& o);
std::vector<CandidateScore> drop_ranking(const DropResidualOutcome& o);

/// Text of the command (without --json): structure, candidates, added, errors, verdict.
std::string residual_text(const std::string& verdict, const ErrorFigures& before, const ErrorFigures& after,
                          const std::vector<CandidateScore>& ranking, const std::vector<EffectAdded>& added,
                          const std::vector<std::string>& notes);
std::string learned_correction_text(const LearnedCorrectionSummary& s);

}  // namespace amb::host::residual
