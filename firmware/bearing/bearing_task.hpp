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
  double aux_radial_clearance_m = 0.7e-3;      ///< rotor-to-aux-bearing radial clearance, m
  double aux_contact_constant_n_per_m1p5 = 0.0;  ///< Hertz constant K of the rotor/aux-race contact, N/m^1.5
  double aux_dynamic_load_rating_n = 0.0;      ///< C of the aux bearing, N (for the Miner fraction)
  double aux_spin_speed_hz = 0.0;              ///< aux inner-race spin assumed during contact, Hz (cycle count)
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

/// Quick-look aux-bearing load estimate of one drop.
/// Model: penetration d = |r| - clearance (r: rotor centre displacement at the aux-bearing
/// plane); contact force F = K d^1.5 for d > 0 (Hertz, no damping); F is binned by contact
/// angle atan2(y, x) into 1-degree bins. Wear proxy (Lundberg-Palmgren-like): damage per bin
/// D = sum F^3 dt [N^3 s] -- L10 life in revolutions scales as (C/P)^3, so the fraction of life
/// used at load P over n revolutions is n (P/C)^3 / 1e6; with n = spin_hz dt the Miner sum is
/// sum (F/C)^3 spin_hz dt / 1e6. Provisional: ignores friction heating, impact dynamics
/// beyond Hertz and the aux bearing's own load distribution.
struct DropLoadEstimate {
  static constexpr int k_bins = 360;
  bool valid = false;                       ///< false on bad input (counted)
  uint32_t samples_in_contact = 0;          ///< samples with penetration > 0
  double peak_force_n = 0.0;                ///< largest contact force, N
  double peak_angle_deg = 0.0;              ///< contact angle of the peak, deg [0, 360)
  double contact_time_s = 0.0;              ///< total time in contact, s
  std::array<double, k_bins> impulse_n_s{};     ///< sum F dt per 1-degree bin, N s
  std::array<double, k_bins> damage_n3_s{};     ///< sum F^3 dt per bin, N^3 s
  double damage_total_n3_s = 0.0;           ///< sum over bins, N^3 s
  double miner_fraction = 0.0;              ///< provisional wear increment, fraction of L10 life (0 if C or spin not set)
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

  /// Quick-look load estimate from a captured drop.
  /// @param x_m, y_m  rotor displacement at the aux-bearing plane, m (same length)
  /// @param dt_s      sample period, s (> 0)
  /// @param out       filled in place (no allocation)
  void estimate_drop_load(std::span<const double> x_m, std::span<const double> y_m, double dt_s,
                          DropLoadEstimate& out) noexcept;
  /// The same with this aux bearing's radial clearance (m, > 0) and the inner-race spin used
  /// for the life fraction (Hz, >= 0; 0: no life fraction) instead of the configured ones.
  void estimate_drop_load_at(std::span<const double> x_m, std::span<const double> y_m, double dt_s,
                             double clearance_m, double spin_hz, DropLoadEstimate& out) noexcept;

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
