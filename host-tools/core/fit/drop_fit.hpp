#pragma once
// Phase C (seed 000 section 2.3): align the drop model with a measured drop by implicit
// filtering over the unknown fault/contact parameters: the friction coefficient (one value
// for both aux bearings, as seed 000), optionally the restitution coefficient and the
// offset of the aux-bearing centres. Known fault parameters (Phase B) are set, not fitted.
// Each cost evaluation restores the levitated pre-drop state (computed once), sets the
// parameters, simulates the event window and compares through drop_cost.hpp.
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/fit/drop_cost.hpp"
#include "host-tools/core/fit/drop_measurement.hpp"
#include "host-tools/core/fit/friction_estimate.hpp"
#include "model/rig/rig_model.hpp"
#include "host-tools/core/fit/implicit_filtering.hpp"
#include "model/drop/drop_options.hpp"
#include "model/drop/drop_simulation.hpp"
#include "model/drop/rubbing_states.hpp"

namespace amb::host::fit {

struct DropFitOptions {
  /// The board's rig model (model/rig), built once by the caller and shared by every model of
  /// the fit (and of the caller's other fits). Null: fit_drop builds it once from the board.
  std::shared_ptr<const model::RigModel> rig_model;
  double mu_min = 0.02, mu_max = 0.6;          ///< friction coefficient bounds, 1
  /// Friction from the contact forces (friction_estimate.hpp: ratio of the tangential to the
  /// normal contact impulse while the collar slides, from the measured orbit's momentum
  /// balance) instead of from the model fit: when the estimate is valid the friction is set to
  /// it and the fit runs over the other unknowns (contact law, drag, ...), which it then
  /// matches to the record with the right friction. Why: a model fitted to the orbit of a
  /// chaotic or backward-whirling drop traded the friction against the contact law (+20-50 %
  /// on backward whirl). Off, or no sliding contact found: the friction is a fit unknown.
  bool friction_from_contact_forces = true;
  FrictionEstimateOptions friction_estimate;   ///< options of that estimate
  // Compliant contact laws (board contact_law "hertz"/"linear"): further unknowns. Ignored
  // under the rigid law. Stiffness fitted as log10 of a factor on the board's value.
  bool fit_contact_stiffness = true;           ///< contact_stiffness_n_per_m
  double stiffness_factor_min = 0.1, stiffness_factor_max = 10.0;  ///< bounds, x the board's, 1
  bool fit_contact_damping = true;             ///< linear contact damping
  double damping_max_n_s_per_m = 4000.0;       ///< bound (lower 0), N s/m
  /// Friction law shape (compliant laws): fit the tanh regularisation velocity eps of the
  /// Coulomb law (log10 range below; micro-slip of a rolling contact), and the exponent of
  /// the spring law f = K d^e between 1 (linear) and 2 (Hertz 1.5 inside). Off by default:
  /// with them the fit needs ~250 evaluations and did not settle better within its budget
  /// (docs/drop-model.md); `amb-host fit --fit-law-shape` switches both on.
  bool fit_slip_regularisation = false;
  double slip_regularisation_min_m_s = 1e-4, slip_regularisation_max_m_s = 0.3;  ///< bounds, m/s
  bool fit_contact_exponent = false;
  double contact_exponent_min = 1.0, contact_exponent_max = 2.0;                 ///< bounds, 1
  bool fit_ring_drag = true;                   ///< ring drag torque (both rings, also under the rigid law)
  double ring_drag_max_n_m = 0.1;              ///< bound (lower 0), N m
  /// After implicit filtering: bounded local polish with NLopt BOBYQA from its best point.
  bool polish = true;
  int polish_max_evaluations = 40;             ///< budget of the polish
  /// Uncertainty of each fitted value: the change that raises the cost by the misfit left at
  /// the optimum (central second difference at uncertainty_step x the range). Heuristic, stated.
  double uncertainty_step = 0.01;              ///< fraction of each range, 1
  bool fit_restitution = false;                ///< also fit e_n
  double restitution_min = 0.05, restitution_max = 0.9;
  bool fit_centre_offset = false;              ///< also fit one (x, y) offset of both bearing centres
  double offset_max_fraction = 0.25;           ///< offset bound, fraction of the clearance
  double max_window_s = 0.4;                   ///< longest event window compared, s
  double settle_s = 0.1;                       ///< levitated settling before the trigger, s
  /// Estimate the rotor's rigid-body position and velocity at the trigger from the measured
  /// free fall (amplifiers off, before the first contact) instead of taking the model's
  /// noise-free levitated state. The chaotic bouncing after the first impacts (and with it
  /// the swing energy, the normal force and the spin-down) depends on the lateral velocity at
  /// the trigger, which the real levitated rotor has from sensor noise and disturbances.
  bool estimate_initial_state = true;
  /// The free fall used for that estimate ends where the measured orbit radius at either aux
  /// bearing first reaches this fraction of the clearance, 1.
  double free_fall_radius_fraction = 0.8;
  /// Fewest free-fall samples the initial-state estimate needs, 1.
  size_t min_free_fall_samples = 10;
  /// No free fall after the trigger (the rotor reached its aux bearing at or right after it:
  /// the board's detection delay after an AMB cut): take the rigid-body state at the trigger
  /// from a quadratic least-squares fit of each sensor over the last pre_trigger_fit_samples
  /// samples up to the trigger (no contact there). Off: keep the model's levitated state.
  bool state_from_pre_trigger = true;
  int pre_trigger_fit_samples = 6;             ///< samples of that fit (>= 3), trigger included
  /// The rotor's flexibility is an uncertain part of the model: fit with the board's modes
  /// and with the rigid-body modes alone (2 per plane; same unknowns, same cost) and keep the
  /// lower cost (DropFitResult::structure_trials lists both). Only when model.modes_per_plane
  /// is 0 (the board's); twice the fit time.
  bool choose_rotor_structure = true;
  model::drop::DropOptions model;              ///< step, restitution, solver (noise is switched off)
  model::drop::RubbingOptions rubbing;
  DropCostWeights weights;
  ImplicitFilteringOptions optimiser;
  std::function<void(const std::string&)> progress;  ///< progress lines (may be empty)
  std::string check() const;                   ///< empty when usable
};

struct DropFitResult {
  double friction_coefficient = 0.0;           ///< fitted or estimated (friction_method), 1
  /// Its uncertainty: the contact-force estimate's (FrictionEstimate::uncertainty) or the
  /// cost curvature's (DropFitOptions::uncertainty_step), 1
  double friction_uncertainty = 0.0;
  /// "contact_forces" (FrictionEstimate, the fit ran over the other unknowns) or "model_fit".
  std::string friction_method = "model_fit";
  FrictionEstimate friction_estimate;          ///< the contact-force estimate (valid = false: not made or none)
  std::string contact_law;                     ///< "rigid", "hertz" or "linear"
  double contact_stiffness_n_per_m = 0.0;      ///< used or fitted (compliant laws), N/m
  double contact_damping_n_s_per_m = 0.0;      ///< used or fitted (compliant laws), N s/m
  double ring_drag_n_m = 0.0;                  ///< used or fitted, N m
  /// Every fitted unknown: name, value, uncertainty (same unit), bounds and whether the value
  /// sits on a bound (within 0.5 % of its range).
  struct Unknown {
    std::string name;
    double value = 0.0, uncertainty = 0.0, lower = 0.0, upper = 0.0;
    bool bound_active = false;
  };
  std::vector<Unknown> unknowns;
  bool bound_active = false;                   ///< any unknown on a bound (then never `converged`)
  std::array<WhirlSummary, 2> whirl{};         ///< measured whirl per aux bearing
  std::array<WhirlSummary, 2> fitted_whirl{};  ///< the fitted simulation's
  double spin_down_rad_s2 = 0.0;               ///< measured spin-down rate (LS slope), rad/s^2
  double fitted_spin_down_rad_s2 = 0.0;        ///< the fitted simulation's, rad/s^2
  /// Sustained backward whirl after lock-in, measured and fitted (valid = false: none; the
  /// cost compares them when cost.lock_in).
  LockInFeatures lock_in, fitted_lock_in;
  int polish_evaluations = 0;                  ///< evaluations of the NLopt polish
  double restitution = 0.0;                    ///< used or fitted, 1
  std::array<double, 2> centre_offset_m{};     ///< fitted common offset (x, y) added to the rig's, m
  std::array<model::drop::RubbingDurations, 2> rubbing{};          ///< fitted simulation, per bearing
  std::array<model::drop::RubbingDurations, 2> measured_rubbing{}; ///< the measurement's, per bearing
  CostBreakdown cost;                          ///< at the fitted parameters
  /// Rigid-body state change applied at the trigger by the free-fall estimate (zero when
  /// not estimated): per rigid mode (x modes, then y modes) position and velocity, modal units.
  std::vector<double> initial_rigid_dq, initial_rigid_du;
  /// Samples used by that estimate: > 0 free fall after the trigger, < 0 (-k) the state at the
  /// trigger from the k samples up to it (DropFitOptions::state_from_pre_trigger), 0 not estimated.
  int free_fall_samples = 0;
  double free_fall_residual_rms_m = 0.0;       ///< RMS sensor residual of that estimate, m
  int evaluations = 0;                         ///< cost evaluations (of every rotor structure tried)
  double wall_s = 0.0;                         ///< host wall time of the fit, s
  bool converged = false;                      ///< optimiser converged AND no bound active
  std::string stop_reason;
  std::vector<double> cost_history;
  model::drop::DropTrace trace;                ///< Phase D record of the fitted simulation (contact steps kept)
  int rotor_modes_per_plane = 0;               ///< lateral modes per plane of the fitted model (2: rigid rotor)
  /// Every rotor structure fitted (DropFitOptions::choose_rotor_structure): modes per plane,
  /// cost at its fit, converged, bound active. The result is the lowest cost's.
  struct StructureTrial {
    int modes_per_plane = 0;
    double cost = 0.0;
    bool converged = false, bound_active = false;
  };
  std::vector<StructureTrial> structure_trials;
};

/// Fit. Throws std::invalid_argument naming the problem for unusable measurement/options.
DropFitResult fit_drop(const DropMeasurement& m, const board::BoardConfig& board, const DropFitOptions& o);

}  // namespace amb::host::fit
