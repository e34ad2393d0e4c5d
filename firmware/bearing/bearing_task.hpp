#pragma once
// Background (non-real-time) bearing task on the board: uses the reduced bearing model for
//  - defect frequencies at a tracked shaft speed (the speed comes from the speed tracker),
//  - effective radial stiffness updates (eq. 8 of seed 003 at the current load and eta, eta
//    written back by the host's identification),
//  - a quick-look auxiliary-bearing contact-load estimate from a captured drop.
// Lifecycle: configure() (validates, sizes everything) -> update calls. Nothing allocates
// after configure(); no exceptions, no locks, no I/O. It is not called per control sample.
#include <array>
#include <cstdint>
#include <span>

#include "model/bearing/geometry.hpp"
#include "model/bearing/hertz_contact.hpp"

namespace amb::fw {

/// Configuration (from the board file).
struct BearingTaskConfig {
  model::bearing::BearingGeometry bearing;     ///< monitored rolling bearing
  double hertz_constant_n_per_m1p5 = 0.0;      ///< k_b,nom, N/m^1.5 (0: model's nominal value)
  double radial_clearance_m = 5e-6;            ///< monitored bearing clearance, m
  double min_speed_hz = 1.0;                   ///< below this a speed is "not running", Hz
  double max_speed_hz = 1000.0;                ///< above this a speed is rejected, Hz
  // Auxiliary (touchdown) bearing quick-look
  double aux_radial_clearance_m = 0.7e-3;      ///< rotor-to-aux-bearing radial clearance, m (both bearings unless given per call)
  double aux_contact_constant_n_per_m1p5 = 0.0;  ///< Hertz constant K of the rotor/aux-race contact, N/m^1.5 (impact peaks)
  double aux_dynamic_load_rating_n = 0.0;      ///< C of the aux bearing, N (for the Miner fraction)
  double aux_spin_speed_hz = 0.0;              ///< aux inner-race spin assumed during contact, Hz (cycle count)
  std::array<double, 2> aux_axial_m{0.0, 1.0}; ///< aux-bearing planes [A, B], m from the rotor's left end
  // Rigid rotor behind the quick-look's momentum balance (from the board's [rig.rotor]).
  double rotor_mass_kg = 0.0;                  ///< total mass, kg (> 0 for the quick-look)
  double rotor_transverse_inertia_kg_m2 = 0.0; ///< about a diameter through the centre of mass, kg m^2 (> 0)
  double rotor_cm_axial_m = 0.5;               ///< centre of mass, m from the left end
  double gravity_m_s2 = 9.81;                  ///< along -y
  /// The rotor counts as in contact where its centre is beyond this fraction of the clearance
  /// (the sensor-plane view of the aux plane is not exact to the micrometre); (0, 1].
  double contact_fraction = 0.95;
  /// Span of the second difference that gives the accelerations, s (each side of the sample):
  /// long enough to average the sensor noise and to null the ringing of the rotor's bending
  /// modes in the sensor-plane view (a +-1 ms difference has zeros at 1 and 2 kHz; the bath
  /// rotor's second free-free bending mode is at 980 Hz), short against a bounce. Impacts
  /// shorter than it are covered by the Hertz impact peak. Rounded to whole samples, >= 1.
  double accel_half_span_s = 1e-3;
};

/// Result of a defect-frequency update.
struct DefectUpdate {
  bool valid = false;          ///< false if the speed was out of range (counted in rejected_speeds)
  double shaft_hz = 0.0;       ///< speed used, Hz
  double ftf_hz = 0.0, bpfo_hz = 0.0, bpfi_hz = 0.0, bsf_hz = 0.0;  ///< Hz
};

/// Result of a stiffness update.
struct StiffnessUpdate {
  bool valid = false;            ///< false if load/eta out of range or no equilibrium found
  double eta = 1.0;              ///< scale in use, dimensionless
  double deflection_m = 0.0;     ///< static radial deflection under the load, m
  double stiffness_n_per_m = 0.0;  ///< effective radial stiffness F/delta (seed 003 eq. 8), N/m
};

/// Quick-look aux-bearing load estimate of one drop, per aux bearing.
/// Model (momentum balance of a rigid rotor, not a contact law on the penetration): the
/// accelerations of the rotor centre at the two aux planes (second differences over
/// +-accel_half_span_s, 1 ms) give the rotor's translational and tilting acceleration; with its mass,
/// transverse inertia and weight they give the two bearing forces on the rotor (AMB forces
/// neglected: the amplifiers are off after a drop; gyroscopic moments neglected). The normal
/// contact force at a bearing is the inward component of its force while the rotor is in
/// contact there (|r| >= contact_fraction x clearance), else 0. At each new contact the Hertz
/// impact peak F = K^0.4 (5/4 m_k v^2)^0.6 (m_k: the bearing's static share of the rotor mass,
/// v: the outward approach speed) stands in for the force where it is larger (an impact lasts
/// less than the differencing span). Why not K d^1.5 on the penetration d = |r| - clearance:
/// real penetrations are a few to tens of micrometres, below what the sensor-plane view of the
/// aux plane resolves (rotor bending in a whirl, sensor noise x the extrapolation, run-out), and
/// with K ~ 3e10 N/m^1.5 an error of 100 um reads as ~30 kN.
/// Forces are binned by contact angle atan2(y, x) into 1-degree bins. Wear proxy
/// (Lundberg-Palmgren-like): damage per bin D = sum F^3 dt [N^3 s] -- L10 life in revolutions
/// scales as (C/P)^3, so the fraction of life used at load P over n revolutions is
/// n (P/C)^3 / 1e6; with n = spin_hz dt the Miner sum is sum (F/C)^3 spin_hz dt / 1e6.
/// Provisional: ignores friction heating and the aux bearing's own load distribution.
struct DropLoadEstimate {
  static constexpr int k_bins = 360;
  bool valid = false;                       ///< false on bad input (counted)
  uint32_t samples_in_contact = 0;          ///< samples with the rotor at the clearance
  uint32_t impacts = 0;                     ///< contacts begun (entries into contact)
  double peak_force_n = 0.0;                ///< largest contact force, N
  double peak_angle_deg = 0.0;              ///< contact angle of the peak, deg [0, 360)
  double peak_impact_force_n = 0.0;         ///< largest Hertz impact peak among the entries, N
  double contact_time_s = 0.0;              ///< total time in contact, s
  std::array<double, k_bins> impulse_n_s{};     ///< sum F dt per 1-degree bin, N s
  std::array<double, k_bins> damage_n3_s{};     ///< sum F^3 dt per bin, N^3 s
  double damage_total_n3_s = 0.0;           ///< sum over bins, N^3 s
  double miner_fraction = 0.0;              ///< provisional wear increment, fraction of L10 life (0 if C or spin not set)
};

/// The rotor centre at both aux-bearing planes over a drop (relative to each aux bearing's
/// centre), sampled every dt_s.
struct DropOrbit {
  std::array<std::span<const double>, 2> x_m{};  ///< [A, B], m (all four the same length)
  std::array<std::span<const double>, 2> y_m{};
  double dt_s = 0.0;                              ///< sample period, s (> 0)
  std::array<double, 2> clearance_m{0.0, 0.0};    ///< per bearing, m; 0: the configured one
  double spin_hz = -1.0;                          ///< inner-race spin for the life fraction, Hz; < 0: the configured one
};

/// Counters of refused inputs (reported, never thrown).
struct BearingTaskCounters {
  uint32_t rejected_speeds = 0;
  uint32_t rejected_stiffness_updates = 0;
  uint32_t rejected_drops = 0;
};

class BearingTask {
 public:
  /// Validate the configuration and precompute. Returns false (task stays unconfigured) if invalid.
  bool configure(const BearingTaskConfig& c);
  bool configured() const { return configured_; }

  /// Defect frequencies at the tracked shaft speed speed_hz (Hz).
  DefectUpdate update_speed(double speed_hz) noexcept;

  /// Set the stiffness scale eta identified on the host (dimensionless, 0.05..20); false if refused.
  bool set_stiffness_scale(double eta) noexcept;

  /// Effective radial stiffness at radial load load_n (N, > 0), cage at angle cage_angle_rad:
  /// solves the bearing's static equilibrium along the load (bisection, <= 60 iterations).
  StiffnessUpdate update_stiffness(double load_n, double cage_angle_rad = 0.0) noexcept;

  /// Quick-look load estimate of both aux bearings from a captured drop (see
  /// DropLoadEstimate). `out` is filled in place (no allocation); both invalid on bad input.
  void estimate_drop_loads(const DropOrbit& orbit, std::array<DropLoadEstimate, 2>& out) noexcept;
  /// Mass behind an impact at aux bearing `bearing` (0: A, 1: B), kg: its static share of the
  /// rotor (lever rule), the mass a parallel drop puts on it. (A tilting impact of one end
  /// meets less, 1 / (1/m + (z - z_G)^2 / I): the share is the conservative choice.)
  double impact_mass_kg(size_t bearing) const noexcept;

  const BearingTaskCounters& counters() const { return counters_; }
  const DefectUpdate& last_defects() const { return last_defects_; }
  const StiffnessUpdate& last_stiffness() const { return last_stiffness_; }

 private:
  bool rebuild_law() noexcept;
  BearingTaskConfig cfg_{};
  model::bearing::HertzContactLaw law_{};
  model::bearing::DefectOrders orders_{};
  double kb_nom_ = 0.0;
  double eta_ = 1.0;
  bool configured_ = false;
  BearingTaskCounters counters_{};
  DefectUpdate last_defects_{};
  StiffnessUpdate last_stiffness_{};
};

}  // namespace amb::fw
