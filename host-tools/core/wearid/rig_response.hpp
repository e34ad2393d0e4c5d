#pragma once
// Steady unbalance response of the rig with its journal bearing, in the frequency domain
// (the forward model of the wear identification; seed 002 section 2.4 with the film
// linearised as in eq. 22-23):
//   rotor: the board's modal reduction (the SIL plant's basis), gyroscopic at the speed,
//          Rayleigh damping;
//   AMBs:  the force law linearised at the static operating point (ks grows with the
//          static coil current: dF/dz = 4 k (i0^2 + ic^2) / g0^3 at z = 0), and each coil
//          pair's current gain at its static gap and load current relative to the board's
//          ki, by which the firmware divides (the actuator plane is not held at zero);
//   loop:  sensors with their first-order roll-off -> (x, y) -> the firmware's discrete PID
//          (backward-difference derivative with its first-order filter, integral updated
//          after the output) -> half a period of zero-order hold -> first-order amplifiers;
//   film:  F = -(K + j w C) q at the journal plane, K and C from the Reynolds solver;
//   load:  the board's disk unbalances at the spin frequency.
// Responses are complex amplitudes referred to the spin angle: x(t) = Re(X e^{j theta(t)}).
// Full spectrum at a probe pair (x' at the first probe, y' at the second, 90 deg
// counter-clockwise from it): forward (+1x) Z+ = (X' + j Y') / 2, backward (-1x)
// Z- = conj(X' - j Y') / 2, so that x' + j y' = Z+ e^{j theta} + Z- e^{-j theta}.
#include <array>
#include <complex>
#include <vector>

#include <Eigen/Core>

#include "firmware/board/board.hpp"
#include "model/journal/reynolds_fvm.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "model/rotor/rotor_model.hpp"

namespace amb::host::wearid {

using cplx = std::complex<double>;

struct FullSpectrum {
  cplx forward_m;   ///< +1x component, m (complex, referred to the spin angle)
  cplx backward_m;  ///< -1x component, m
};

/// Steady response at the journal probes with the full (nonlinear) film: +-1x, +-2x (+-3x).
struct FullFilmSpectrum {
  FullSpectrum first;            ///< +1x / -1x, m (referred to the spin angle)
  FullSpectrum second;           ///< +2x / -2x, m (referred to twice the spin angle)
  FullSpectrum third;            ///< +3x / -3x, m (thrice the spin angle); zero with 2 harmonics
  std::vector<std::array<cplx, 2>> journal_m;  ///< (x, y) at the journal plane of harmonics 1..N of the balance, m
  std::array<double, 2> mean_force_n{};  ///< film force averaged over the orbit, N
  int harmonics = 2;             ///< highest harmonic of the spin in the balance
  int iterations = 0;            ///< harmonic-balance iterations used
  bool converged = false;        ///< last update below the tolerance
};

/// Highest harmonic of the spin the harmonic balance can carry.
inline constexpr int k_max_harmonics = 6;

/// Settings of the harmonic balance (RigResponse::journal_probes_full_film).
struct HarmonicBalanceOptions {
  int samples = 32;              ///< Reynolds solves (and AMB-law samples) per revolution, >= 8
  int max_iterations = 40;       ///< fixed-point iterations at most, >= 1
  double tolerance = 1e-5;       ///< update norm, relative to the linear journal orbit
  const FullFilmSpectrum* start = nullptr;  ///< a nearby solution to start from (e.g. the previous wear's)
  bool amb_nonlinear = false;    ///< the AMBs' force law beyond its linearisation
  bool film_nonlinear = true;    ///< the film beyond its linearisation (false: linear, as the SIL's default element)
  int harmonics = 2;             ///< highest harmonic of the spin kept: 2..k_max_harmonics (and < samples / 2)
};

class RigResponse {
 public:
  /// `board` must have a [journal_bearing]; `static_force_n` is the film force at the static
  /// journal position at `speed_hz` (it sets the AMBs' static currents). Throws
  /// std::invalid_argument naming what is missing.
  RigResponse(const board::BoardConfig& board, double speed_hz, std::array<double, 2> static_force_n);

  /// Full spectrum at the journal probes for film coefficients at this speed (K in N/m,
  /// C in N s/m, rotordynamic sign: F = -K q - C q').
  FullSpectrum journal_probes(const Eigen::Matrix2d& k_n_per_m, const Eigen::Matrix2d& c_n_s_per_m) const;
  /// Same at another speed (coefficients given for that speed): for run-up responses.
  FullSpectrum journal_probes_at(double speed_hz, const Eigen::Matrix2d& k_n_per_m,
                                 const Eigen::Matrix2d& c_n_s_per_m) const;
  /// Full spectra at the journal probes and at the two AMB sensor planes (probe pairs
  /// [A1, A2] and [B1, B2]), in that order.
  std::array<FullSpectrum, 3> all_probes(const Eigen::Matrix2d& k_n_per_m, const Eigen::Matrix2d& c_n_s_per_m) const;
  /// Complex amplitudes (x, y) at the journal plane, m.
  std::array<cplx, 2> journal_xy_at(double speed_hz, const Eigen::Matrix2d& k_n_per_m,
                                    const Eigen::Matrix2d& c_n_s_per_m) const;

  double speed_hz() const { return speed_hz_; }
  /// Modal response (x modes then y modes) at a speed.
  Eigen::VectorXcd modal_response(double speed_hz, const Eigen::Matrix2d& k_n_per_m, const Eigen::Matrix2d& c_n_s_per_m) const;
  /// The journal probes' +-1x and +-2x (and +-3x) with the full Reynolds film (`solver`, the
  /// bore and its wear) about the journal's mean position `mean` (m, velocities 0), by
  /// harmonic balance. Two nonlinear forces are split into their linearisation (in the closed
  /// loop's dynamic matrix A) and a remainder: with `o.film_nonlinear` the film at the journal
  /// plane (linearised by `lin` at `mean`, K, C for this response's speed; remainder's
  /// harmonics by model::journal::film_harmonics, `o.samples` solves per iteration) and, with
  /// `o.amb_nonlinear`, each AMB's force law (model/amb/amb_force.hpp) about its static gap
  /// and current, along the orbit of its actuator plane and the control current the loop
  /// commands (the quadratic law makes a 2x of its own: at e = 0.7 about 0.02 um at the
  /// journal probes). The modal responses at the harmonics k = 1..H (H = `o.harmonics`) solve
  ///   A(k W) E_k = [k = 1] F_unbalance + B^T R_k(E_1, ..., E_H)
  /// by Anderson-accelerated fixed-point iteration from the linear response (or from
  /// `o.start`'s journal orbit) until the update is below `o.tolerance` times the linear
  /// response or `o.max_iterations`. Harmonics above H are neglected: with H = 2 the 3x the
  /// orbit makes (and its products with the 1x, which feed the 2x) are missing. Throws
  /// std::invalid_argument when the orbit touches the bore or an option is out of range.
  FullFilmSpectrum journal_probes_full_film(model::journal::ReynoldsSolver& solver, const model::journal::JournalState& mean,
                                            const model::journal::DynamicCoefficients& lin,
                                            const HarmonicBalanceOptions& o = {}) const;
  /// Receptance at the journal plane: complex displacement amplitudes (x, y), m, per unit
  /// complex force amplitude (x, y), N, applied at the journal plane at `excitation_hz`
  /// (any frequency, e.g. a harmonic of the spin), with the rotor spinning at `spin_hz`
  /// (gyroscopics) and the film's linear coefficients K (N/m), C (N s/m) for that spin.
  /// Column c is the response to a unit force along axis c.
  Eigen::Matrix2cd journal_receptance(double spin_hz, double excitation_hz, const Eigen::Matrix2d& k_n_per_m,
                                      const Eigen::Matrix2d& c_n_s_per_m) const;
  /// Re-linearise the AMBs for another static film force (N, x y): the static AMB forces and
  /// positions are linear in it (precomputed at construction), so this is cheap.
  void set_static_film_force(std::array<double, 2> force_n);

 private:
  // Dynamic stiffness of the closed loop in modal coordinates (x modes then y modes) at an
  // excitation frequency, spinning at spin_hz.
  Eigen::MatrixXcd dynamic_matrix(double spin_hz, double excitation_hz, const Eigen::Matrix2d& k_n_per_m,
                                  const Eigen::Matrix2d& c_n_s_per_m) const;
  // Force demand per unit sensor-plane displacement of AMB b at `w_rad_s` (N/m, complex): the
  // sensor roll-off, the discrete PID with its notches, the half-period hold, the amplifier.
  cplx loop_gain(size_t b, double w_rad_s) const;
  // Harmonics 1..H of the AMB force-law remainder (law - its linearisation) along the orbit of
  // modal responses e[k-1] at k x the spin (H = e.size()), as modal forces (x modes then y
  // modes), N.
  std::vector<Eigen::VectorXcd> amb_remainder(const std::vector<Eigen::VectorXcd>& e, double w_rad_s, int samples) const;
  board::BoardConfig b_;
  double speed_hz_ = 0.0;
  model::rotor::RotorModel fe_;
  model::rotor::ReducedRotor red_;
  int m_ = 0;
  std::array<Eigen::RowVectorXd, 2> b_amb_, b_sensor_;
  Eigen::RowVectorXd b_journal_;
  Eigen::VectorXd unb_s_, unb_c_;
  std::array<Eigen::Matrix2d, 2> ks_xy_;   // per AMB: linearised negative stiffness in (x, y), N/m
  std::array<Eigen::Matrix2d, 2> ki_xy_;   // per AMB: local current gain / board ki in (x, y), 1
  // Per AMB and actuator axis: the static gap offset (m) and control current (A), and the
  // local linearisation there.
  std::array<std::array<double, 2>, 2> axis_z0_m_{}, axis_ic0_a_{}, axis_ks_{}, axis_ki_{};
  // Static AMB force/position per unit film force: st0 + fx * stx + fy * sty.
  std::array<std::array<std::array<double, 2>, 2>, 3> amb_force_basis_{}, amb_disp_basis_{};
  std::array<std::array<double, 2>, 2> probe_dir_{};
  std::array<std::array<double, 2>, 4> sensor_dir_{};
};

}  // namespace amb::host::wearid
