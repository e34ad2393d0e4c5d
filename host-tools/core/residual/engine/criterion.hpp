#pragma once
// The one keep/reject criterion of the residual loop, for every record kind (steady run, drop
// event, sweep, journal record). A record kind supplies, per candidate element, what the
// decision reads -- nothing else: the per-kind code has no keep rules of its own.
//
// The criterion, stated once:
//   keep  <=>  delta_ic > min_delta_ic                  (the element earns its parameters on
//                                                        the likelihood of the reproducible
//                                                        features: an information criterion)
//         and  effect_sigma >= min_effect_sigma          (its predicted change of the
//                                                        features exceeds the record's noise)
//         and  identified                                (its own parameters inside their
//                                                        physical bounds and not
//                                                        interchangeable with another's)
//         and  no decision feature rises by more than feature_tolerance, and one falls by at
//              least min_relative_improvement (half of it with delta_ic >= strong_delta_ic)
// Decision features are features a model can reproduce (levitated spectra and lines, static
// positions, contact geometry, FRF, film orbit harmonics), each with a noise level estimated
// from the record. Information features (e.g. the chaotic post-impact trajectory of a drop)
// are reported before and after but never decide.
//
// min_delta_ic is calibrated on clean records: docs/residual.md gives the false-alarm rate per
// element measured on a population of generated clean drops (with its 95 % interval).
#include <string>
#include <utility>
#include <vector>

namespace amb::host::residual::engine {

/// One figure of a record under the model without and with a candidate element.
struct Feature {
  std::string name;               ///< what it is ("contact misfit", "spectral error", "aux bearing 1 centre", ...)
  std::string unit;               ///< unit of before/after ("1", "dB", "sigma", "um", ...)
  double before = 0.0;            ///< under the current model
  double after = 0.0;             ///< with the element, refitted
  bool higher_is_better = false;  ///< Pearson-like figures
  /// The feature only counts towards "one falls" when `before` exceeds this (a figure already
  /// at its noise floor cannot fall materially), in its unit.
  double counts_above = 0.0;
  /// A rise only vetoes when `after` exceeds this, in its unit (0: every rise counts): a
  /// feature that stays inside the record kind's own significance floor (e.g. an aux-bearing
  /// centre closer to the model's than the smallest offset the drop part claims) has not
  /// risen materially.
  double rises_above = 0.0;
};

/// What a record kind hands the engine for one candidate.
struct CandidateEvidence {
  std::string element;            ///< catalogue name (engine/elements.hpp)
  bool testable = true;           ///< false: the record cannot test it (reason in `evidence`)
  std::string evidence;           ///< where in the residual it was seen, in words with figures
  double delta_ic = 0.0;          ///< information-criterion decrease (BIC(current) - BIC(with it)), 1
  std::string ic_basis;           ///< which likelihood delta_ic is computed on (noise model stated)
  double effect_sigma = 0.0;      ///< largest predicted change of a decision feature, in noise standard errors
  bool identified = true;         ///< own parameters within bounds, not interchangeable with another's
  std::string not_identified;     ///< why not, when not
  std::vector<Feature> decision;  ///< decide
  std::vector<Feature> information;  ///< reported only (chaotic remainder, classic figures not decided on)
};

/// The criterion's settings (one set for every record kind; the record kinds' options hold one).
struct Criterion {
  double min_delta_ic = 10.0;             ///< information-criterion decrease to earn the parameters (calibrated: docs/residual.md)
  double min_effect_sigma = 3.0;          ///< predicted change beyond the record's noise, standard errors
  double min_relative_improvement = 0.10; ///< a decision feature must fall by at least this fraction
  double strong_delta_ic = 300.0;         ///< with delta_ic at least this, half of min_relative_improvement suffices
  double feature_tolerance = 0.01;        ///< a decision feature changing by less than this fraction counts as unchanged
  /// Empty when valid, else what is wrong (names the setting).
  std::string check() const;
};

/// The decision on one candidate: kept or not, the criterion's value against its threshold,
/// and the reason in words (every failed condition, or why it is kept).
struct Decision {
  bool kept = false;
  double value = 0.0;       ///< delta_ic
  double threshold = 0.0;   ///< min_delta_ic
  std::string reason;
};

Decision decide(const CandidateEvidence& c, const Criterion& k);

/// Relative change (after - before) / |before| of a feature, signed so that < 0 is better.
double relative_change(const Feature& f);

}  // namespace amb::host::residual::engine
