#pragma once
// One axis of the discrete PID position controller (seed 002 eq. 19), in force units:
//   F = -(K_P e + K_I \int e dt + K_D de/dt),   e = q - q_ref
// with a first-order filtered derivative, clamped integrator with conditional integration
// (anti-windup), an optional first-order lead, optional notch filters, and output saturation. The caller divides by k_i.
// Real-time: step() does not allocate, lock or throw.
#include <array>

#include "model/control/pid_params.hpp"

namespace amb::fw {

/// Discretised second-order notch, direct form I (Tustin with pre-warping).
struct Biquad {
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;  ///< normalised coefficients (a0 = 1)
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;          ///< state
  double step(double x);
  void reset() { x1 = x2 = y1 = y2 = 0; }
};

/// Design a notch biquad: centre, -3 dB width and residual depth at the centre.
Biquad design_notch(const model::NotchParams& n, double sample_rate_hz);
/// Design the first-order lead (1 + s/wz) / (1 + s/wp) as a biquad (b2 = a2 = 0), Tustin.
Biquad design_lead(double zero_hz, double pole_hz, double sample_rate_hz);

class PidAxis {
 public:
  /// Fixed at configure: gains, limits, loop rate (Hz), force-to-current gain ki (N/A) used
  /// to express the saturation limit in force.
  void configure(const model::PidParams& p, double rate_hz, double ki_n_per_a);
  /// Clear the state. Call with the set-point placed at the present position, so the
  /// error and its derivative start at zero.
  void reset();
  /// One period. `q_m`: measured position, `q_ref_m`: set-point. Returns the force demand, N,
  /// already saturated to current_limit_a * ki. `saturated` reports saturation this step.
  double step(double q_m, double q_ref_m, bool& saturated);
  double integral_force_n() const { return integral_n_; }
  /// Start the integrator at a known static force (e.g. the weight share), N; clamped to
  /// the integrator limit. The output convention is F = -(... + integral), so a lifting
  /// force F is preloaded as -F.
  void preload_force(double force_n);

 private:
  model::PidParams p_{};
  double dt_s_ = 1e-4;
  double deriv_alpha_ = 0.0;      ///< filter pole exp(-2 pi f_c dt)
  double force_limit_n_ = 0.0;
  double integral_n_ = 0.0;       ///< K_I \int e dt, N
  double prev_error_m_ = 0.0;
  double deriv_m_s_ = 0.0;        ///< filtered de/dt, m/s
  std::array<Biquad, model::k_max_notches> notch_{};
  bool has_lead_ = false;
  Biquad lead_{};                 ///< optional lead on the output (before the notches)
};

}  // namespace amb::fw
