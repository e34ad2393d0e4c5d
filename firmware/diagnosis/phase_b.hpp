#pragma once
// Phase B on the board (seed 000, Fig. 2): identify the fault behind a frozen capture window,
// in the paper's order, from the control currents and the rotor orbit only:
//   1. channel cut-off      — a control current ~0 while its demand is not;
//   2. current disturbance  — the control currents change BEFORE the deflection does, at a
//                             frequency that is not the rotor speed (frequency found by a
//                             Goertzel scan of the currents after the change);
//   3. changing unbalance   — the 1x synchronous orbit radius (DFT at the speed estimate over
//                             whole revolutions) rises over the pre-trigger history;
//   4. misalignment         — the centre of the mean orbit moves while its radius stays;
//   5. otherwise            — not a modeled fault.
// Runs in the non-real-time event thread (allocates). It sees only the recorded samples and
// the sensor calibration: never what was injected.
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "firmware/app/loop_sample.hpp"

namespace amb::fw::diag {

/// Values are stored in event files: append only, never renumber.
enum class FaultType : uint8_t {
  not_modeled = 0,
  channel_cutoff = 1,
  current_disturbance = 2,
  changing_unbalance = 3,
  misalignment = 4,
  not_evaluated = 255,  ///< window too short to evaluate
};
/// Stable names: "not_modeled", "channel_cutoff", "current_disturbance",
/// "changing_unbalance", "misalignment", "not_evaluated".
const char* to_string(FaultType t);

/// Thresholds of the identification (defaults suit 10 kHz boards with ~1 um sensor noise).
struct DiagnosisOptions {
  // 1. cut-off
  double cutoff_min_demand_a = 0.1;       ///< |demand| above this counts as "demanded", A
  double cutoff_ratio = 0.1;              ///< |measured| < ratio |demand| (or < cutoff_zero_a) is "no current"
  double cutoff_zero_a = 0.01;            ///< A
  double cutoff_min_run_s = 1.5e-3;       ///< consecutive samples of "demanded but no current", s (>> amplifier lag)
  // 2. disturbance
  double baseline_fraction = 0.4;         ///< first part of the pre-trigger history used as baseline
  double onset_window_s = 2e-3;           ///< moving-RMS window of the change statistic, s
  double onset_threshold = 5.0;           ///< change statistic (baseline standard deviations)
  double onset_margin_s = 0.1;            ///< search for the onset up to trigger + this, s
  double min_current_lead_s = 0.5e-3;     ///< current change must lead the deflection change by this, s
  double disturbance_min_hz = 5.0;        ///< below: a drift, not a disturbance, Hz
  double disturbance_max_hz = 1000.0;     ///< scan limit (also < 0.45 rate), Hz
  double min_explained = 0.3;             ///< fraction of the current change a sinusoid must explain
  double max_spectrum_s = 1.0;            ///< at most this much data after the onset is scanned, s
  // 3./4. orbit
  double min_speed_hz = 3.0;              ///< below: no synchronous analysis, Hz
  double unbalance_min_growth_m = 5e-6;   ///< 1x radius growth over the history, m
  double unbalance_min_relative = 0.25;   ///< ... and relative to the first radius
  double misalignment_min_shift_m = 10e-6;///< centre movement over the history, m
  double misalignment_max_radius_relative = 0.25; ///< radius may change at most this much
  double window_s = 0.05;                 ///< analysis window when not spinning, s
};

/// What the board knows about the window.
struct DiagnosisInput {
  std::span<const LoopSample> samples;    ///< the frozen window
  size_t trigger_index = 0;               ///< index of the trigger sample
  double rate_hz = 0.0;                   ///< loop rate, Hz
  std::array<double, 4> sensor_angle_deg{45.0, -45.0, 45.0, -45.0};  ///< [A1, A2, B1, B2], deg from vertical
};

/// The Phase B result: fault type, its parameters (known and estimated) and a confidence.
struct Diagnosis {
  FaultType type = FaultType::not_evaluated;
  double confidence = 0.0;                ///< 0..1
  // cut-off (known parameter: current factor 0 on the cut channels)
  uint8_t cutoff_channels = 0;            ///< bit i: axis i cut off
  std::array<double, 4> current_factor{1.0, 1.0, 1.0, 1.0};
  // disturbance (known: frequency; amplitude is an estimate, refined in Phase C)
  double disturbance_frequency_hz = 0.0;
  double disturbance_amplitude_a = 0.0;   ///< largest per-channel amplitude at that frequency, A
  uint8_t disturbance_channels = 0;       ///< channels carrying it (amplitude > 30 % of the largest)
  double current_lead_s = 0.0;            ///< current change before deflection change, s (<0: after)
  // unbalance (unknown parameter; the 1x radius trend is the evidence)
  double speed_hz = 0.0;                  ///< mean speed estimate over the history, Hz
  std::array<double, 2> radius_1x_start_m{};  ///< 1x orbit radius per plane at the start of the history, m
  std::array<double, 2> radius_1x_end_m{};    ///< ... at the trigger, m
  // misalignment (known: direction; angle unknown)
  std::array<double, 2> centre_shift_m{};     ///< centre movement per plane over the history, m
  double misalignment_direction_deg = 0.0;    ///< direction of the centre movement, deg from upward vertical towards +x
  int misalignment_plane = -1;                ///< plane with the larger movement (0: A, 1: B)
  std::string summary;                        ///< one line for operators (<= 255 chars)
};

/// Identify the fault. Never throws on data; returns not_evaluated when the window is too short.
Diagnosis diagnose(const DiagnosisInput& in, const DiagnosisOptions& o = {});

}  // namespace amb::fw::diag
