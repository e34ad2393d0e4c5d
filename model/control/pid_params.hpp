#pragma once
// Parameters of the per-axis AMB position controller (seed 002 eq. 19):
//   i_c = (K_P q + K_I \int q dt + K_D dq/dt) / k_i
// Shared by the firmware's discrete implementation and the model's linearised analysis.
#include <array>

namespace amb::model {

/// A second-order notch (band-stop) filter on the controller output.
struct NotchParams {
  double centre_hz = 0.0;   ///< notch centre frequency, Hz (> 0)
  double width_hz = 0.0;    ///< -3 dB bandwidth, Hz (> 0)
  double depth = 0.0;       ///< residual gain at the centre, 0 (full notch) .. 1 (no notch)
};

inline constexpr int k_max_notches = 4;

struct PidParams {
  double kp_n_per_m = 0.0;          ///< proportional gain, N/m (force per displacement)
  double ki_n_per_m_s = 0.0;        ///< integral gain, N/(m s)
  double kd_n_s_per_m = 0.0;        ///< derivative gain, N s/m
  double derivative_filter_hz = 0.0;///< first-order low-pass on the derivative term, Hz
  double integrator_limit_n = 0.0;  ///< anti-windup: |K_I \int q| is clamped to this force, N
  double current_limit_a = 0.0;     ///< output saturation of the control current, A (per actuator axis)
  /// Optional first-order lead on the controller output, (1 + s/wz) / (1 + s/wp): unit gain at
  /// DC, phase lead between the zero and the pole, gain pole/zero above. Both 0: no lead.
  double lead_zero_hz = 0.0;        ///< zero of the lead, Hz (< lead_pole_hz)
  double lead_pole_hz = 0.0;        ///< pole of the lead, Hz
  std::array<NotchParams, k_max_notches> notches{};  ///< optional notches (centre_hz == 0: unused)
  int notch_count = 0;              ///< number of notches in use
};

}  // namespace amb::model
