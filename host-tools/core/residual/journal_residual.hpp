#pragma once
// The residual loop on a steady record of a rig with a hydrodynamic journal bearing (seed 002):
// the element `journal_bearing_wear`. The board's model (rotor, AMB loop, the film of the
// bore the board declares, usually unworn) predicts the +1x / -1x full-spectrum components at
// the journal probes at the recorded speed (host-tools/core/wearid/rig_response.hpp); the
// residual against the measured ones (journal_spectrum.hpp) is what the element must explain.
// The candidate is the elliptical three-parameter wear of the bore (d0, gamma, beta; seed 002
// eq. 8-13), fitted by the wear identification (DOE + NLopt BOBYQA multistart). It is added
// or rejected by the engine's one criterion (engine/criterion.hpp), as every element of every
// record kind. What this record kind hands it:
//  - delta_ic: the BIC decrease (Gaussian likelihood with the record's own off-bin noise per
//    component, 3 parameters, 4 real data),
//  - decision feature: the spectral error (the +1x / -1x components' misfit),
//  - effect_sigma: the predicted components with and without the wear, in noise standard errors,
//  - identified: each fitted parameter's 1-sigma (record noise through the Jacobian at the
//    fit) within `max_sigma_of_range` of its bound range (an element whose parameters the
//    data do not fix is not named).
// The loop is never told whether or how the bearing is worn: it reads the event and the board.
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/loaded_event.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"

namespace amb::host::residual {

struct JournalResidualOptions {
  engine::Criterion criterion;             ///< the one keep/reject criterion (engine/criterion.hpp)
  double max_sigma_of_range = 0.25;        ///< each fitted parameter's 1-sigma must be within this fraction of its bound range, 1
  /// The wear fit (3p). Depth bounds start at 1 um so that "no wear" is nearly inside the family.
  wearid::WearIdOptions wear = [] {
    wearid::WearIdOptions o;
    o.model = model::journal::WearModel::elliptical;
    o.depth_um = {1.0, 150.0};
    o.profile_likelihood = false;  // the loop decides on its own identifiability rule, not on wear-id's intervals
    return o;
  }();
};

/// Misfit of a model at the journal probes.
struct JournalErrors {
  double spectral = 0.0;     ///< |Z_model - Z_measured| / |Z_measured| over (+1x, -1x), 1
  double forward_m = 0.0;    ///< |dZ+|, m
  double backward_m = 0.0;   ///< |dZ-|, m
  double chi2 = 0.0;         ///< sum of squared real residuals / (noise per real component)^2, 1
  double bic = 0.0;          ///< chi2 + k ln(4), k = parameters of the elements, 1
};

struct JournalResidualOutcome {
  wearid::JournalMeasurement measured;
  std::string declared_wear;               ///< the board's wear ("none", "2p", "3p")
  JournalErrors before, after;
  double effect_sigma = 0.0;               ///< candidate's predicted change in noise standard errors
  double delta_bic = 0.0;                  ///< BIC(before) - BIC(with the candidate)
  double relative_improvement = 0.0;       ///< 1 - after.spectral / before.spectral of the candidate
  double worst_sigma_of_range = 0.0;       ///< largest fitted 1-sigma / bound range, 1
  wearid::WearIdResult fit;                ///< the candidate's fit
  std::vector<CandidateScore> ranking;
  std::vector<EffectAdded> effects_added;
  std::vector<std::string> notes;
  std::string verdict;                     ///< "none" or "journal_bearing_wear"
};

/// True when the board has a [journal_bearing] and the event has its two probes and a key
/// phasor (what the journal path needs); `why` says what is missing otherwise.
bool is_journal_event(const LoadedEvent& ev, const board::BoardConfig& b, std::string* why = nullptr);

/// Run the journal path of the residual loop. Throws std::invalid_argument when the event is
/// not a journal record (see is_journal_event).
JournalResidualOutcome run_journal_residual(const LoadedEvent& ev, const board::BoardConfig& b,
                                            const JournalResidualOptions& o = {});

/// The outcome as the JSON object `amb-host residual --json` prints.
std::string journal_residual_json(const JournalResidualOutcome& r);
/// The outcome as the text report.
std::string journal_residual_text(const JournalResidualOutcome& r);

}  // namespace amb::host::residual
