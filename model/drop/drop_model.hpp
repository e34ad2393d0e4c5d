#pragma once
// Non-smooth multibody drop model of an AMB rotor on its auxiliary bearings (seed 000
// Phase C, section 3): the finite-element rotor of model/rotor, modally reduced; two
// nonlinear AMBs (model/amb) with amplifier lag and the PlantFaults of the SIL plant; an
// optional internal discrete PID (same law and gains as the firmware) for a realistic
// levitated state before the drop; disk unbalance; gravity (-y); the rotor's spin DOF (drive
// only while the amplifiers are on); two auxiliary bearings as rigid unilateral contacts
// with Coulomb friction against inner rings that have their own spin DOF and a dry drag
// torque.
//
// Time stepping on velocity level (Moreau-Jean, seed 000 eq. 3-16): per step h
//   1. smooth forces (AMB, unbalance, faults) at the predicted midpoint q + h u / 2;
//   2. free velocity from the midpoint (trapezoidal) rule of the linear rotor, implicit in
//      stiffness, damping and gyroscopics: A u_free = (2I - A) u - h K q + h f,
//      A = I + h/2 (C + Omega G) + h^2/4 K (modal, mass-normalised);
//   3. contacts closed when the gap at the predicted end q + h u is <= 0; contact normal at
//      the predicted midpoint; impulses from contact_solver.hpp (Newton impact law with
//      restitution e_n, Coulomb friction, ring drag) on the Delassus W^T A^-1 W (6 x 6);
//   4. u+ = u_free + A^-1 W L, q += h (u + u+)/2.
// The linear part is energy-exact (midpoint rule) and every impulse does non-positive work
// on the step-average velocity, so with the AMBs off total energy + dissipation is
// constant to round-off (energy_ledger()). The method is order 1 in h across impacts.
//
// Compliant laws (board key contact_law = "hertz" | "linear", or DropOptions::contact_law):
// the same midpoint step with the contact forces as impulses of compliant_contact.hpp (Hertz
// or linear spring with linear / Hunt-Crossley damping, never pulling; exact or tanh-
// regularised Coulomb friction against each ring's spin DOF; exact ring drag), the spring
// linearised over the step (trapezoidal, A-stable), and the step cut to
// DropOptions::contact_step_s while a contact is closed or about to close (explicit-free:
// stable at any step; the sub-step is for accuracy). No position projection (penetration is
// the law). The contact potential energy is part of mechanical_energy_j(); impact_dissipated_j
// then books the normal damping work.
//
// Frames as rotor_amb_plant.hpp: y up, x right, z along the rotor, spin about +z; sensor
// zero = AMB centres; aux-bearing centres at their offsets. Contact polar angles follow the
// board convention: degrees from the upward vertical, positive towards +x (the bottom of a
// bearing is 180 deg); a positive spin (about +z) moves a point from +x towards +y, i.e. to
// DEcreasing polar angle.
//
// Real time: step() does not allocate (fixed-capacity Eigen storage), lock or throw.
// Model and data are separate: parameters and the reduction are fixed after construction
// (the fit's setters are configure-time calls); DropState holds everything that changes,
// so a state can be saved and restored (e.g. the levitated state at a drop's trigger).
#include <array>
#include <cstdint>

#include <Eigen/Core>

#include "model/amb/amb_force.hpp"
#include "model/control/pid_params.hpp"
#include "model/drop/compliant_contact.hpp"
#include "model/drop/contact_solver.hpp"
#include "model/drop/drop_options.hpp"
#include "model/plant/gaussian_rng.hpp"
#include "model/plant/plant.hpp"
#include "model/rig/rig_model.hpp"
#include "model/rig/step_rows.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model::drop {

inline constexpr int k_max_modes = k_step_max_modes;   ///< capacity: modes per lateral plane
inline constexpr int k_max_lateral = 2 * k_max_modes;  ///< capacity: lateral modal DOFs (x then y)
using ModeVec = StepModeVec;
using ModeMat = StepModeMat;
using LatVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, k_max_lateral, 1>;
using LatMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, k_max_lateral, k_max_lateral>;
using LatBasis = Eigen::Matrix<double, Eigen::Dynamic, 4, 0, k_max_lateral, 4>;

/// Contact data of one Moreau-Jean step, for Phase D storage and the Phase E load map.
struct StepContact {
  double t_s = 0.0;                        ///< time at the end of the step, s
  double h_s = 0.0;                        ///< step length, s
  std::array<bool, 2> active{};            ///< contact closed in this step
  std::array<double, 2> normal_n{};        ///< normal impulse / h (mean normal force), N
  std::array<double, 2> friction_n{};      ///< friction impulse / h on the rotor along t = z x n, N
  std::array<double, 2> angle_deg{};       ///< contact-point polar angle (board convention), deg
  std::array<double, 2> slip_m_s{};        ///< step-average slip velocity collar - ring, m/s
  std::array<double, 2> friction_power_w{};///< friction work dissipated / h (>= 0), W
};

/// Cumulative energy balance (J). With the amplifiers off and no unbalance,
/// energy_now + dissipated_total - external_work == energy at reset (to round-off).
struct EnergyLedger {
  double external_work_j = 0.0;      ///< work of AMB, unbalance, misalignment and drive forces
  double damping_dissipated_j = 0.0; ///< Rayleigh damping of the rotor
  double impact_dissipated_j = 0.0;  ///< normal impulses (Newton law), >= 0 per step
  double friction_dissipated_j = 0.0;///< collar/ring Coulomb friction, >= 0 per step
  double ring_drag_dissipated_j = 0.0;///< inner-ring bearing drag, >= 0 per step
  double projection_energy_j = 0.0;  ///< potential-energy change by the position projection (not dissipation)
  double min_step_contact_dissipation_j = 0.0; ///< smallest per-step impulse dissipation seen (must not be < -round-off)
  double dissipated_total_j() const {
    return damping_dissipated_j + impact_dissipated_j + friction_dissipated_j + ring_drag_dissipated_j;
  }
};

/// Everything that changes while stepping (the model's "data").
struct DropState {
  LatVec q, u;                              ///< modal displacements (x modes, then y modes) and velocities
  double t_s = 0.0;
  double spin_rad_s = 0.0, spin_angle_rad = 0.0, spin_accel_rad_s2 = 0.0;
  std::array<double, 2> ring_rad_s{}, ring_angle_rad{};
  std::array<double, 4> current_a{};        ///< actual control current per actuator axis, A
  std::array<double, 4> demand_a{};         ///< internal controller's current demand, A
  std::array<double, 4> amb_force_n{};      ///< force per actuator axis, N
  std::array<double, 4> sensor_filtered_m{}, sensor_out_m{};
  // Internal PID per bearing-frame axis [Ax, Ay, Bx, By].
  std::array<double, 4> pid_integral_n{}, pid_prev_error_m{}, pid_deriv_m_s{};
  double controller_clock_s = 0.0;          ///< time since the last controller update, s
  LocalVec warm_impulse = LocalVec::Zero(); ///< last step's contact impulses (warm start)
  StepContact last_contact;                 ///< last step's contact data
  EnergyLedger ledger;
  std::array<double, 2> contact_energy_j{};  ///< compliant laws: elastic contact energy now, J
  PlantFaults faults;
  GaussianRng rng;
};

/// Counted, never thrown, while stepping.
struct DropCounters {
  std::uint64_t steps = 0;               ///< Moreau-Jean steps
  std::uint64_t contact_steps = 0;       ///< steps with a closed contact
  std::uint64_t solver_unconverged = 0;  ///< steps whose PGS hit the sweep cap
  int solver_max_sweeps = 0;             ///< most sweeps one step needed
  std::uint64_t refactorisations = 0;    ///< rebuilds of A^-1 (spin changed)
  double max_penetration_m = 0.0;        ///< worst gap violation at a step end (velocity-level drift; compliant: deepest contact), m
  std::uint64_t contact_substeps = 0;    ///< compliant laws: sub-steps of contact_step_s taken
};

/// Receives every Moreau-Jean step's contact data (e.g. for the load map). Called from step().
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual void on_step(const StepContact& c) = 0;
};

class DropModel final : public Plant {
 public:
  /// Builds the FE rotor and its reduction (allocates; configure time). `pid` and
  /// `controller_rate_hz` (Hz) are the board's controller, used when
  /// options.internal_controller is set. Throws std::invalid_argument for unusable input.
  DropModel(const PlantParams& plant, const PidParams& pid, double controller_rate_hz, const DropOptions& options);
  /// The same on a rig model built once elsewhere (shared, read only; see model/rig). `plant`
  /// carries what the fit varies (friction, offsets, contact law, unbalance); its rotor and
  /// planes must be the rig model's. options.modes_per_plane cuts the rig model's modal basis
  /// (no new FE build or eigen solve).
  DropModel(std::shared_ptr<const RigModel> rig, const PlantParams& plant, const PidParams& pid,
            double controller_rate_hz, const DropOptions& options);

  // model::Plant
  void reset(bool levitated, double spin_hz) override;
  void step(double dt_s, const PlantInputs& in) override;
  PlantOutputs outputs() const override;
  PlantTruth truth() const override;
  void set_faults(const PlantFaults& faults) override;

  // Configure-time changes used by the fit (no effect on the state).
  void set_friction_coefficient(double mu);                     ///< both bearings, 1
  void set_restitution(double e);                               ///< Newton e_n, 1
  void set_aux_centre_offset(int bearing, double x_m, double y_m); ///< bearing centre, m
  // Compliant laws (both bearings; no effect under the rigid law):
  void set_contact_stiffness(double n_per_m);   ///< contact_stiffness_n_per_m (dF/dd at d_ref), N/m
  void set_contact_damping(double n_s_per_m);   ///< linear contact damping c, N s/m
  void set_slip_regularisation(double m_s);     ///< 0: exact Coulomb, else tanh(v / eps), m/s
  void set_ring_drag(double n_m);               ///< ring drag torque, both bearings, N m
  /// Exponent e of f(d) = K d^e (1.5 Hertz, 1 linear; fitted shapes in between), K keeps the
  /// contact stiffness df/dd at d_ref. Compliant laws only, e in [1, 2].
  void set_contact_exponent(double e);
  double contact_exponent() const { return law_exp_; }
  /// The law in use (the board's or DropOptions::contact_law).
  AuxContactLaw contact_law() const { return contact_law_; }
  bool compliant() const { return contact_law_ != AuxContactLaw::rigid; }
  void set_observer(StepObserver* observer) { observer_ = observer; }

  const DropState& state() const { return s_; }
  /// Restore a saved state. The cached step matrices are dropped too, so that a simulation
  /// from a restored state does not depend on what ran before (the matrices are rebuilt when
  /// the spin drifts by 0.1 %: a cache from another run would differ by up to that much, and
  /// chaotic contact motion amplifies it; the fit's evaluations must be reproducible).
  void restore(const DropState& s) {
    s_ = s;
    for (auto& mm : mats_) mm.h = -1.0;
  }
  const DropCounters& counters() const { return counters_; }
  void clear_counters() { counters_ = DropCounters{}; }
  const EnergyLedger& energy_ledger() const { return s_.ledger; }
  /// Mechanical energy now: lateral kinetic + spin + rings + elastic + gravity (zero at the
  /// sensor zero), J. Magnetic field energy is not included (the AMBs are an input).
  double mechanical_energy_j() const;

  const PlantParams& params() const { return p_; }
  const DropOptions& options() const { return o_; }
  int modes_per_plane() const { return m_; }
  /// Squared natural frequencies of the free-free modes of one plane, rad^2/s^2 (exactly 0
  /// for the rigid-body modes; mass-normalised: q and u of a mode are in sqrt(kg) m, sqrt(kg) m/s).
  const ModeVec& modal_omega2() const { return rows_.w2; }
  double step_s() const { return o_.step_s; }
  double rotor_mass_kg() const { return rig_->mass_kg(); }
  const std::shared_ptr<const RigModel>& rig_model() const { return rig_; }
  double spin_inertia_kg_m2() const { return rows_.spin_inertia_kg_m2; }
  /// Rotor centre (x, y) at an axial position now, m (truth; allocates: not for the loop).
  std::array<double, 2> displacement_at(double axial_m) const;
  /// Rotor centre at aux-bearing plane `bearing` now, m.
  std::array<double, 2> aux_position_m(int bearing) const;

 private:
  struct StepMatrices {
    double h = -1.0, spin = 0.0;
    LatMat a_inv;          // A^-1
    LatBasis z;            // A^-1 [b_aux0 in x, b_aux0 in y, b_aux1 in x, b_aux1 in y]
    Eigen::Matrix4d s_aux; // B^T A^-1 B
    double lag_h = -1.0;   // step of the lag factors below
    std::array<double, 2> amp_alpha{};
    std::array<double, 4> sensor_alpha{};
  };
  void substep(double h, const PlantInputs& in);
  void advance(double h, const PlantInputs& in, StepMatrices& mats);
  bool compliant_contact_near(double h) const;
  double contact_force_n(size_t b, double d_m) const;
  double contact_energy_at(size_t b, double d_m) const;
  void controller_update(double period_s);
  void project_positions(const std::array<bool, 2>& closed);
  void refactor(double h, double spin_rad_s, StepMatrices& mats);
  double lateral_at(const ModeVec& b, const LatVec& v, int axis) const;

  PlantParams p_;
  PidParams pid_;
  double ctrl_period_s_ = 0.0;
  DropOptions o_;
  ContactSolverOptions solver_{};
  std::shared_ptr<const RigModel> rig_;  // shared, read only
  RigReduction red_;                     // the rig model's rows at this model's mode count
  int m_ = 0;

  // Reduced model (fixed after construction): the rig model's rows, this model's laws and
  // unbalance.
  StepRows rows_;
  std::array<std::array<double, 4>, 2> sensor_inv_{}, actuator_inv_{};  // per bearing 2x2 inverses
  std::array<double, 2> ring_radius_m_{};

  // Step matrices for the current (h, spin): [0] the normal step, [1] the contact sub-step.
  std::array<StepMatrices, 2> mats_;
  AuxContactLaw contact_law_ = AuxContactLaw::rigid;
  std::array<double, 2> law_k_{};       // compliant: f(d) = law_k_ d^law_exp_
  double law_exp_ = 1.0;

  // Per step() call: forces held over the call (misalignment drift, unbalance growth) and
  // the exact first-order lag factors of amplifiers and sensors for the sub-step length.
  ModeVec fext_x_, fext_y_, unb_s_step_, unb_c_step_;

  DropState s_;
  DropCounters counters_{};
  StepObserver* observer_ = nullptr;
};

}  // namespace amb::model::drop
