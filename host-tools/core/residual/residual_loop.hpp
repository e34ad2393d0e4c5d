#pragma once
// The residual loop on a steady-state record: fit the board's model, look at the residual's
// structure, rank the candidate model elements by how much each earns (BIC), add the top
// one and refit everything, keep it only if the BIC falls by more than `min_delta_bic`,
// repeat while something significant remains.
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/residual/engine/criterion.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/residual/steady_fit.hpp"

namespace amb::host::residual {

struct LoopOptions {
  /// The one keep/reject criterion (engine/criterion.hpp): an element must lower the BIC by
  /// more than criterion.min_delta_ic, its predicted change of the signals must exceed
  /// criterion.min_effect_sigma standard errors of the record's noise at some band, line,
  /// static value or rest reading (effect_size_sigma), no reported error may rise and the
  /// spectral, rms or rest-position error must fall by criterion.min_relative_improvement
  /// (a statistically "significant" fix of a 4 % PSD mismatch is a modelling detail, not a
  /// missing effect; half of it with a BIC decrease >= criterion.strong_delta_ic).
  engine::Criterion criterion;
  /// The board's rig model (model/rig), built once by the caller and shared by every model
  /// evaluation; null: run_residual_loop builds it once.
  std::shared_ptr<const model::RigModel> rig_model;
  int max_effects = 3;           ///< elements added at most
  int max_evaluations = 50;      ///< per refinement
  /// Fit the base model's own uncertain parameters (loop delay, force scale; EffectSet::update)
  /// before any element is tried.
  bool update_model = true;
};

/// A part of the residual that no element explains (after the loop), with its structure.
struct UnexplainedItem {
  std::string part = "levitated"; ///< "levitated" (steady loop) or "drop" (drop part of a drop event)
  std::string kind;        ///< "band" (fixed-frequency PSD excess or deficit), "order" (speed-locked line), or
                           ///< (drop part) "contact_compliance" (deflection growing with the contact force at one bearing)
  double f_hz = 0.0;       ///< band centre or line frequency, Hz
  int order = 0;           ///< speed order (kind "order"), else 0
  int plane = -1;          ///< bearing plane carrying most of it (0 = A, 1 = B)
  double level_db = 0.0;   ///< band: measured / model PSD, dB (smoothed over 3 bands, mean of the plane's channels)
  double snr = 0.0;        ///< order: residual line power / its noise power
  std::string direction;   ///< order: "forward" or "backward" whirl of the residual line (full spectrum)
  double amplitude_m = 0.0; ///< order: residual line amplitude at that plane, m
  double f_hi_hz = 0.0;    ///< drop-part band: upper end of a run of adjacent bands (f_hz its lower end), Hz
  double value = 0.0;      ///< contact_compliance: compliance beyond the other bearing's, m/N
};

/// Full-spectrum (seed 002) components of one bearing plane at one speed order:
/// z = x + j y, forward at +h*spin, backward at -h*spin (amplitudes, m).
struct FullSpectrumLine {
  int plane = 0, order = 1;
  double forward_measured_m = 0.0, backward_measured_m = 0.0;
  double forward_residual_m = 0.0, backward_residual_m = 0.0;
};

struct ResidualStructure {
  std::vector<std::pair<double, double>> resonance_excess;  ///< (f Hz, dB) peaks of measured/model PSD
  std::vector<std::pair<double, double>> resonance_deficit; ///< (f Hz, dB) model peaks the data lacks
  std::array<double, k_orders> order_excess_snr{};          ///< residual line power / noise, per order
  double subsynchronous_excess_db = 0.0;                    ///< mean measured/model PSD below the speed, dB
  double static_current_ratio = 1.0;                        ///< |measured| / |model| static currents
  std::array<double, 4> rest_offset_m{};                    ///< rest readings minus model, m (0 without rest)
  bool has_rest = false;
  double current_phase_lag_deg = 0.0;                       ///< model minus measured current-to-displacement phase at 1x, deg
  std::array<double, k_channels> channel_rms_residual{};    ///< time-domain residual RMS per channel (m, A)
  std::array<double, 2> orbit_residual_max_m{};             ///< largest residual orbit radius per sensor plane, m
  std::vector<FullSpectrumLine> full_spectrum;
  std::vector<std::string> notes;                           ///< human-readable findings
};

struct CandidateScore {
  std::string name;
  bool testable = true;
  double delta_bic = 0.0;        ///< BIC(current) - BIC(with it), > 0: it earns its parameters
  std::string evidence;
  // The engine's decision (engine/criterion.hpp), when the candidate reached it.
  bool decided = false;          ///< false: screened out before a refit (the reason is in `evidence`)
  bool kept = false;
  double threshold = 0.0;        ///< the criterion's threshold on delta_bic
  std::string reason;            ///< kept or rejected, and why
  std::vector<engine::Feature> decision_features;     ///< decided on, before -> after
  std::vector<engine::Feature> information_features;  ///< reported only (e.g. a drop's chaotic remainder)
};

/// The candidate's score with the engine's decision on it.
CandidateScore scored(const engine::CandidateEvidence& c, const engine::Decision& d);

struct EffectAdded {
  std::string name;
  std::vector<std::pair<std::string, double>> parameters;
  std::string evidence;
  double delta_bic = 0.0;
};

struct ModelUpdateReport {
  bool done = false;
  double loop_delay_s = 0.0;      ///< fitted extra loop delay, s
  double force_scale = 1.0;       ///< fitted actuator force constant / board's, 1
  double force_noise_rms_n = 0.0; ///< fitted force disturbance, N rms per sample and axis
  double noise_rms_m = 0.0;       ///< fitted sensor noise, m rms per sample
  double delta_bic = 0.0;         ///< BIC(board values) - BIC(updated)
  bool at_bound = false;          ///< a fitted value on its bound (not identified): the first element's errors are judged against the board model
};

struct ResidualOutcome {
  SteadyEvaluation before, after;
  SteadyEvaluation updated;                  ///< the base model after model updating (= before when not done)
  ModelUpdateReport model_update;
  std::vector<UnexplainedItem> unexplained;  ///< what remains after the loop, beyond the noise
  ResidualStructure structure;               ///< of the residual before anything was added
  ResidualStructure structure_after;
  std::vector<CandidateScore> ranking;       ///< first round, best first
  std::vector<EffectAdded> effects_added;
  std::string verdict;                       ///< "none", else the added names joined with "+"
};

/// Structure of the residual of an evaluation.
ResidualStructure analyse_structure(const SteadyData& d, const board::BoardConfig& b, const SteadyEvaluation& ev);

/// Named parameters of an element in a set (SI units in the names).
std::vector<std::pair<std::string, double>> effect_parameters(const model::effects::EffectSet& e,
                                                              model::effects::EffectKind k);

/// Largest predicted change of the signals between two evaluations of one record, in standard
/// errors of the record's noise: PSD bands |ln P_a - ln P_b| sqrt(averages); speed-order lines
/// |dY| / sqrt(2 P / T); statics and rest readings against their likelihood's standard deviation.
double effect_size_sigma(const SteadyData& d, const board::BoardConfig& b, const SteadyEvaluation& with,
                         const SteadyEvaluation& without);

/// The structure of what remains: bands and speed-order lines beyond the noise.
std::vector<UnexplainedItem> unexplained_items(const SteadyData& d, const board::BoardConfig& b, const SteadyEvaluation& ev,
                                               const ResidualStructure& st);

ResidualOutcome run_residual_loop(const SteadyData& d, const board::BoardConfig& b, const LoopOptions& o = {});

}  // namespace amb::host::residual
