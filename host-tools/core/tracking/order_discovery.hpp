#pragma once
// Order discovery for track-speed: which shaft speed and which orders of it a record shows,
// from the whole record, before tracking (docs/tracking.md "Order discovery").
//
// Averaged spectrum (Welch, Hann, 50 % overlap, segment_s long). A line is present if its
// prominence over the block-median floor exceeds the level that averaged noise (chi-squared
// with 2K degrees of freedom for K averaged segments) exceeds with probability
// false_alarm / (bins searched). A candidate speed f in [min, max] scores the summed excess
// prominence of its present orders 1..max_order (its 1x must be present: a shaft's lowest line
// is its 1x; the comb ends at two missing orders in a row) minus the present half orders (k - 1/2) f (what f would leave unexplained if it
// were twice the true speed). The best candidate is the discovered speed; it is "ambiguous" if
// a candidate that is not a simple ratio of it (p/q, p, q <= 4) scores at least
// ambiguity_ratio x as much: two unrelated line families, and nothing in the record says which
// one is the shaft.
#include <string>
#include <vector>

namespace amb::host {

struct OrderDiscoveryOptions {
  double min_speed_hz = 8.0;        ///< lowest candidate speed, Hz
  double max_speed_hz = 300.0;      ///< highest candidate speed, Hz
  int max_order = 8;                ///< orders 1..max_order are looked for; [1, 8]
  double segment_s = 1.0;           ///< Welch segment, s (clipped to a third of the record)
  double false_alarm = 1e-3;        ///< chance that noise makes any searched bin a "line"
  double ambiguity_ratio = 0.5;     ///< runner-up / best score above which the result is ambiguous
  double line_tolerance = 0.01;     ///< relative half width searched around k f (speed drift in the record)
  double target_prominence_db = 20.0;  ///< window choice: the strongest line should reach this
  double max_accel_hz_per_s = 150.0;   ///< search range of the per-segment 1x (coarse track)
};

struct OrderDiscovery {
  bool found = false;               ///< a candidate with a present 1x exists
  bool ambiguous = false;           ///< an unrelated candidate scores nearly as well
  double speed_hz = 0.0;            ///< discovered speed, Hz (valid if found)
  std::vector<double> orders;       ///< present orders of it, ascending
  std::vector<double> prominence_db;  ///< their prominences, dB (same order)
  double score = 0.0;               ///< summed excess prominence, dB
  double runner_up_hz = 0.0;        ///< best unrelated candidate, Hz (0: none)
  double runner_up_score = 0.0;
  double threshold_db = 0.0;        ///< presence threshold, dB above the floor
  double segment_s = 0.0;           ///< Welch segment used, s
  double bin_hz = 0.0;              ///< spectrum bin spacing, Hz
  double window_s = 0.5;            ///< window from the line SNR (target_prominence_db) and >= 12 / speed, s
  bool resolved = true;             ///< false: the window cap is shorter than 12 / speed (1x too close to DC)
  std::string reason;               ///< one sentence
  /// Coarse track: per Welch segment, its centre time (s) and the 1x peak (Hz) near the
  /// discovered speed, where that peak stands above the presence threshold of one segment.
  std::vector<double> coarse_t_s, coarse_hz;
};

/// Discover speed and orders in x (any unit) sampled at fs_hz. `max_window_s` caps the
/// recommended window (drift limit, record length). Throws std::invalid_argument on bad input.
OrderDiscovery discover_orders(const std::vector<double>& x, double fs_hz, const OrderDiscoveryOptions& o,
                               double max_window_s);

}  // namespace amb::host
