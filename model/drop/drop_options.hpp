#pragma once
// Options of the non-smooth drop model (drop_model.hpp). Defaults are the stated model
// choices of docs/drop-model.md.
#include <cmath>
#include <cstdint>
#include <string>

namespace amb::model::drop {

/// Contact law used by the drop model: the board's choice (AuxBearingParams::contact_law,
/// board key `[[rig.aux_bearing]] contact_law`) or an override.
enum class ContactLawChoice : int { board = 0, rigid = 1, hertz = 2, linear = 3 };

/// Coefficient K of the spring law f(d) = K d^e whose contact stiffness df/dd at the reference
/// penetration d_ref is `stiffness_n_per_m`: K = k / (e d_ref^(e - 1)) (e = 1: K = k; Hertz
/// e = 1.5: K = k / (1.5 sqrt(d_ref))). The contact stiffness of a non-linear contact is its
/// tangent (linearised) stiffness, the one that sets the contact's natural frequency; it is
/// 1/e of the secant F/d at the same penetration, which an earlier version used.
inline double contact_law_coefficient(double stiffness_n_per_m, double exponent, double d_ref_m) {
  return stiffness_n_per_m / (exponent * std::pow(d_ref_m, exponent - 1.0));
}
/// The inverse: the contact stiffness df/dd at d_ref of f(d) = K d^e, N/m.
inline double contact_law_stiffness(double coefficient, double exponent, double d_ref_m) {
  return coefficient * exponent * std::pow(d_ref_m, exponent - 1.0);
}

struct DropOptions {
  /// Moreau-Jean time step h, s. Order-1 method (velocity jumps): the step-halving test in
  /// tests/drop shows the error; 2e-5 s keeps ~30 steps per period of the fastest whirl seen.
  double step_s = 2.0e-5;
  /// Newton restitution coefficient e_n of the collar/ring impact, 1, in [0, 1]. Not in
  /// seed 000 (rigid contact); 0.3 is a steel-on-steel value for impacts of a few 0.1 m/s.
  double restitution = 0.3;
  /// Projected Gauss-Seidel: stop when no impulse update changes its own local velocity by
  /// more than this, m/s; and the sweep cap. Unconverged steps are counted, not thrown.
  double solver_tolerance_m_s = 1.0e-10;
  int solver_max_iterations = 200;
  /// Lateral modes kept per plane (rigid-body modes included); 0: the board's modes_kept.
  int modes_per_plane = 0;
  /// true: the model runs the AMB position controller itself (a discrete PID per
  /// pid_params.hpp at the board's loop rate, same law as the firmware: sensors -> bearing
  /// frame -> PID -> actuator forces -> currents). false: the inputs' current demands are
  /// used (the model is the plant under the firmware in SIL).
  bool internal_controller = true;
  /// With the internal controller: model the amplifiers' first-order lag (board
  /// amplifier_bandwidth_hz)? Off by default: with the Bath board's 275 Hz lag the board's PID
  /// gains have a negative phase margin (about -19 deg at the 1.2 krad/s crossover, see
  /// docs/drop-model.md) and the levitated state diverges; the drop itself happens with the
  /// amplifiers off, so only the pre-drop state depends on this.
  bool internal_amplifier_lag = false;
  /// With the internal controller: measure at the actuator planes (collocated) instead of
  /// the board's sensor planes? On by default: in this FE rotor the board's non-collocated
  /// sensors (50 mm outboard of the AMBs) let the PID destabilise the first bending mode
  /// (spill-over; stable with rigid-body modes only). Collocated PD is passive.
  bool internal_controller_collocated = true;
  /// Project the positions back onto the clearance circle after a step that ends with a
  /// closed contact penetrating (velocity-level schemes drift by O(h^2) per step in fast
  /// whirl). Minimal modal-mass-norm displacement along the contact normals; its potential-
  /// energy change is booked separately in the ledger (projection_energy_j).
  bool position_projection = true;
  // ---- Compliant contact laws ("hertz", "linear"; see compliant_contact.hpp) ----
  /// Which law: the board's (default) or an override for both bearings.
  ContactLawChoice contact_law = ContactLawChoice::board;
  /// Step used while a compliant contact is closed or about to close, s (the step_s step is
  /// cut into ceil(step_s / contact_step_s) equal sub-steps; no cut when step_s is smaller). 5 us resolves a contact of
  /// 1e8-3e8 N/m on the ~1 kg effective mass at a collar (period >= 0.4 ms) by >= 80 steps.
  double contact_step_s = 5.0e-6;
  /// A closed compliant contact is "quiet" when its normal velocity changes the penetration
  /// by at most this share of it over one step_s step (rolling at the bottom, sustained whirl);
  /// while every near contact is quiet the step is not cut. 0: always cut near a contact.
  /// The sub-step test in tests/drop (CompliantContact.ContactSubStepConverges) holds the
  /// default to the same error as cutting every step, 1.
  double quiet_contact_share = 0.1;
  /// Hertz law F = K d^1.5: K = contact_stiffness_n_per_m / (1.5 d_ref^0.5), i.e. the contact
  /// stiffness dF/dd (tangent) at d_ref equals the board's contact_stiffness_n_per_m
  /// (contact_law_coefficient below). d_ref, m.
  double hertz_reference_penetration_m = 1.0e-5;
  /// Hunt-Crossley damping: F = f(d) (1 + alpha d') + c d', alpha in s/m (0: off, only the
  /// board's linear contact_damping_n_s_per_m c). Never pulling.
  double hunt_crossley_s_per_m = 0.0;
  /// Coulomb friction at the collar: exact (set-valued, 0) or regularised tanh(v / eps)
  /// with eps in m/s. Only for the compliant laws (the rigid law is always exact).
  double slip_regularisation_m_s = 0.0;
  /// Sensor noise on/off and its seed (deterministic).
  bool sensor_noise = true;
  std::uint64_t noise_seed = 1;

  /// Empty when usable, else what is wrong.
  std::string check() const {
    if (!(step_s > 0.0 && step_s <= 1e-3)) return "step_s must be in (0, 1e-3] s";
    if (!(restitution >= 0.0 && restitution <= 1.0)) return "restitution must be in [0, 1]";
    if (!(solver_tolerance_m_s > 0.0)) return "solver_tolerance_m_s must be > 0";
    if (solver_max_iterations < 1) return "solver_max_iterations must be >= 1";
    if (modes_per_plane < 0) return "modes_per_plane must be >= 0";
    if (!(contact_step_s > 0.0 && contact_step_s <= 1e-3)) return "contact_step_s must be in (0, 1e-3] s";
    if (!(quiet_contact_share >= 0.0 && quiet_contact_share <= 1.0)) return "quiet_contact_share must be in [0, 1]";
    if (!(hertz_reference_penetration_m > 0.0 && hertz_reference_penetration_m < 1e-2))
      return "hertz_reference_penetration_m must be in (0, 1e-2) m";
    if (!(hunt_crossley_s_per_m >= 0.0 && hunt_crossley_s_per_m < 1e3)) return "hunt_crossley_s_per_m must be in [0, 1e3) s/m";
    if (!(slip_regularisation_m_s >= 0.0 && slip_regularisation_m_s < 10.0))
      return "slip_regularisation_m_s must be in [0, 10) m/s";
    return {};
  }
};

}  // namespace amb::model::drop
