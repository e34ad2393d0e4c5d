#pragma once
// The simulated rig: a modally reduced flexible rotor on two nonlinear AMBs, with current
// amplifiers (first-order lag, limits), non-collocated noisy sensors (first-order roll-off),
// gravity (-y), disk unbalance, the spin DOF with a speed-controlled drive, and two
// auxiliary bearings with a penalty contact and regularised Coulomb friction against inner
// rings that spin on their own (see aux_contact.hpp). Faults per PlantFaults.
//
// Integrator: semi-implicit (symplectic) Euler on a fixed sub-step h, one force evaluation
// per sub-step. Stiffness is explicit; Rayleigh damping is implicit (diagonal in modal
// coordinates); the gyroscopic coupling is applied as a norm-preserving rotation of the
// modal velocities (second-order Cayley form), so spin neither adds nor removes energy; the
// contact friction is implicit in the slip velocity; the AMB force of a sub-step uses the
// coil current at its start, which then follows its held command exactly, and the sensor
// roll-off is exact for a displacement moving linearly over the sub-step (so neither lag
// leads its continuous counterpart). Sub-step rule: h <= 0.2 / w_max, w_max the largest of the highest
// kept free-free mode and each contact frequency sqrt(k_contact / m_eff), and
// h <= 0.5 m_eff / c_contact; the board's integration_step_s is used if it is smaller.
// Symplectic Euler is stable for w h < 2; 0.2 keeps ~30 sub-steps per period of the
// fastest motion, which keeps the contact impacts resolved (RK4 would cost four force
// evaluations per step and its order is lost at the contact's kinks anyway).
//
// Frames: y up, x right, z along the rotor, spin about +z. Sensor zero = AMB centres; the
// aux-bearing centres sit at their offsets from it. Angles (actuators, sensors, unbalance
// phase) are degrees from the upward vertical towards +x; a positive spin turns the
// unbalance from +x towards +y (its angle decreases). The coupling (misalignment fault) is
// at the right end, z = rotor length.
//
// Real time: step() does not allocate (fixed-capacity Eigen storage), lock or throw.
#include <cstdint>
#include <memory>

#include <Eigen/Core>

#include "model/amb/amb_force.hpp"
#include "model/journal/journal_rig.hpp"
#include "model/plant/aux_contact.hpp"
#include "model/plant/gaussian_rng.hpp"
#include "model/plant/plant.hpp"
#include "model/rig/rig_model.hpp"
#include "model/rig/step_rows.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::model {

class RotorAmbPlant final : public Plant {
 public:
  static constexpr int k_max_modes = k_step_max_modes;  ///< capacity: modes per lateral plane
  using Vec = StepModeVec;
  using Mat = StepModeMat;

  struct Options {
    std::uint64_t noise_seed = 1;               ///< sensor-noise seed (deterministic)
    double slip_regularisation_m_s = 1e-3;      ///< friction regularisation velocity, m/s
    double ring_regularisation_rad_s = 0.1;     ///< ring drag regularisation speed, rad/s
    /// Aux-bearing contact law of the plant: 1 linear penalty (default), 1.5 Hertz (K d^1.5,
    /// dF/dd = the board's contact stiffness at 10 um). Test-data generators vary it.
    double contact_exponent = 1.0;
  };

  /// Counted, never thrown, while stepping.
  struct Counters {
    std::uint64_t substeps = 0;
    std::uint64_t contact_substeps = 0;         ///< sub-steps with any contact
    std::uint64_t current_limited_steps = 0;    ///< steps where a demand hit coil_current_limit_a
    std::uint64_t film_refused_steps = 0;       ///< steps whose full-film solve was refused (set_journal_film)
  };

  /// Builds the FE model and its reduction (allocates; configure time). Throws
  /// std::invalid_argument for parameters it cannot simulate (e.g. more than k_max_modes).
  explicit RotorAmbPlant(const PlantParams& p);
  RotorAmbPlant(const PlantParams& p, const Options& o);
  /// The plant on a rig model built once elsewhere (shared, read only). `p` carries what this
  /// plant varies (offsets, friction, unbalance, noise, ...); its rotor and planes must be the
  /// rig model's (std::invalid_argument naming the difference otherwise).
  RotorAmbPlant(std::shared_ptr<const RigModel> rig, const PlantParams& p, const Options& o);

  void reset(bool levitated, double spin_hz) override;
  void step(double dt_s, const PlantInputs& in) override;
  PlantOutputs outputs() const override;
  PlantTruth truth() const override;
  void set_faults(const PlantFaults& faults) override;

  double integration_step_s() const { return h_nominal_s_; } ///< sub-step in use, s
  double step_rule_s() const { return h_rule_s_; }           ///< largest sub-step the rule allows, s
  double rotor_mass_kg() const { return rig_->mass_kg(); }
  double spin_inertia_kg_m2() const { return rows_.spin_inertia_kg_m2; }
  const rotor::RotorModel& rotor_model() const { return rig_->rotor(); }
  const rotor::ReducedRotor& reduced_rotor() const { return rig_->board_reduction().reduced; }
  const std::shared_ptr<const RigModel>& rig_model() const { return rig_; }
  const PlantParams& params() const { return p_; }
  const Counters& counters() const { return counters_; }
  /// Rotor displacement (x, y) at any axial position now, m (truth).
  std::array<double, 2> displacement_at(double axial_m) const;

  /// Optional hydrodynamic journal bearing (seed 002, see model/journal/journal_rig.hpp):
  /// a linearised film force F = (W / W0)(F0 - K dq) - C dq' at its plane. Configure time
  /// (allocates; tightens the sub-step rule for the film's stiffness and damping). Passing
  /// an element with enabled = false removes it.
  void set_journal(const journal::LinearJournal& j);
  const journal::LinearJournal& journal() const { return journal_; }
  /// Full (nonlinear) Reynolds film on top of the linear element (opt-in; nullptr: linear
  /// element only, the default). Each step() solves the Reynolds problem once, at the
  /// journal state predicted for the middle of the step (position, velocity and the last
  /// step's acceleration) and the current spin, and adds the difference between that film
  /// force and the linear element's force at the same state, held over the step's sub-steps.
  /// The linear element keeps the sub-steps stable; the held difference carries the film's
  /// second- and higher-order terms (harmonics of the orbit, a shift of the mean force). The
  /// solver must describe the same bore (geometry, wear) as the element and is owned by the
  /// plant from here on. A state the solver refuses (film <= 0) adds no difference and is
  /// counted in film_refused_steps. Host-side simulation only: the solve is not real-time safe
  /// (sparse factorisation, ~0.1-0.5 ms per step).
  void set_journal_film(std::shared_ptr<journal::ReynoldsSolver> solver);
  bool journal_film_nonlinear() const { return film_ != nullptr; }
  /// Journal probes now (with noise, updated each step): displacement from the bore centre
  /// along each probe direction, m. Zero without a journal bearing.
  std::array<double, 2> journal_probe_m() const { return journal_probe_m_; }
  /// Film force on the rotor during the last sub-step, N (x, y).
  std::array<double, 2> journal_force_n() const { return journal_force_n_; }

 private:
  void substep(double h, const PlantInputs& in);
  double contact_energy_j() const;

  PlantParams p_;
  Options o_;
  std::shared_ptr<const RigModel> rig_;       // shared, read only
  int m_ = 0;                                 // modes per plane
  double h_rule_s_ = 0.0, h_nominal_s_ = 0.0;

  // Reduced model (fixed capacity): the rig model's rows, this plant's laws and unbalance.
  StepRows rows_;
  std::array<double, 2> aux_inv_mass_{};

  // State.
  Vec ex_, ey_, vx_, vy_;                     // modal displacements and velocities
  double t_s_ = 0.0, spin_rad_s_ = 0.0, spin_angle_rad_ = 0.0, spin_accel_rad_s2_ = 0.0;
  std::array<double, 2> ring_rad_s_{};
  std::array<double, 4> current_a_{};         // actual control current per actuator axis
  std::array<double, 4> bias_a_{};            // actual bias current per actuator axis (lags on switch-on)
  std::array<double, 4> sensor_filtered_m_{};
  std::array<double, 4> sensor_true_m_{};     // sensed displacement before the roll-off, at t
  std::array<double, 4> sensor_out_m_{};
  double friction_dissipated_j_ = 0.0;
  PlantFaults faults_{};
  GaussianRng rng_;

  // Last sub-step's forces (truth).
  std::array<ContactResult, 2> contact_{};
  std::array<double, 4> amb_force_n_{};

  // Per-step constants.
  Vec fconst_x_, fconst_y_, unb_s_step_, unb_c_step_;
  std::array<double, 2> amp_alpha_{};
  double amp_h_ = -1.0;
  std::array<double, 4> sensor_alpha_{}, sensor_ramp_{};
  Vec kick_den_, journal_u_;                  // 1 + h damp (per mode); D^-1 b_journal (see substep)
  double journal_g_ = 0.0;                    // b_journal . journal_u_

  Counters counters_{};

  // Journal bearing (optional).
  journal::LinearJournal journal_{};
  Vec b_journal_;
  std::array<std::array<double, 2>, 2> journal_probe_dir_{};
  std::array<double, 2> journal_probe_m_{}, journal_force_n_{};
  std::shared_ptr<journal::ReynoldsSolver> film_;
  std::array<double, 2> film_extra_n_{};        // full film minus linear element, held over a step, N
  std::array<double, 2> film_prev_v_m_s_{};     // journal velocity at the previous step, m/s
  double film_prev_dt_s_ = 0.0;
};

}  // namespace amb::model
