#pragma once
// Host-side speed tracking of a recorded channel: optional anti-alias decimation, then the
// on-board SpeedRidgeTracker (model/signal) over the whole record. The input is a plain
// vector + sample rate so any reader (mat files, event files) can feed it.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host-tools/core/tracking/machine_profile.hpp"
#include "host-tools/core/tracking/order_discovery.hpp"
#include "model/signal/speed_ridge_tracker.hpp"

namespace amb::host {

/// Settings of a host tracking run.
struct TrackSpeedOptions {
  /// Tracker settings. tracker.stft.sample_rate_hz is overwritten with the rate after
  /// decimation; everything else is used as given.
  model::signal::SpeedTrackerOptions tracker{};
  /// Decimation factor: 0 = automatic, 1 = none, N = decimate by N.
  /// Automatic: the largest M with fs/M >= 2.5 * (largest order * max_speed_hz + 2 *
  /// search_half_band_hz) and window samples after decimation >= 0.61 nfft (seed 003's
  /// zero padding); M = 1 if that gives less than 2; at least large enough for the window
  /// to fit into nfft.
  size_t decimate = 0;

  /// Empty if valid for input rate `fs_hz`; otherwise a message naming the bad field.
  std::string validate(double fs_hz) const;
};

/// Result of a host tracking run, one entry per tracker update.
struct TrackSpeedResult {
  std::vector<double> t_s;         ///< window-centre time of each update, s from the first sample
  std::vector<double> speed_hz;    ///< shaft speed, Hz; NaN where lost
  std::vector<double> confidence;  ///< ridge confidence in [0, 1]
  std::vector<bool> lost;          ///< true: no valid speed for this update
  std::vector<bool> below_min;     ///< true: the track fell below the stated minimum
  model::signal::SpeedTrackerSummary summary{};
  size_t decimation = 1;           ///< decimation factor used
  double tracker_rate_hz = 0.0;    ///< sample rate seen by the tracker, Hz
  /// Profile runs (track_speed_with_profile): "ok", "ambiguous" (two unrelated line families,
  /// every update lost), "no_line" (nothing stands out, every update lost), "unresolved" (the
  /// record is too short for a window that resolves the speed, every update lost); "fixed" for
  /// track_speed() with the caller's comb.
  std::string status = "fixed";
  bool profiled = false;           ///< true: track_speed_with_profile() produced this
  OrderDiscovery discovery{};      ///< what order discovery found (profile runs)
  double window_s = 0.0;           ///< STFT window used, s
  size_t rejected_updates = 0;     ///< updates set lost by the consistency check (profile runs)
};

/// Track with a machine profile (machine_profile.hpp) instead of per-run flags: the comb is
/// the profile's or discovered (order_discovery.hpp), the window is chosen from the line SNR
/// (<= record/2, <= sqrt(8 / max_accel) s so a linear drift at the limit stays within a few
/// bins), the first lock is searched around the discovered speed, and an update further from
/// the discovered speed than the acceleration limit allows over its distance from the record
/// centre (+1 %) is reported lost. An ambiguous or empty discovery gives every update lost.
/// Constants of the profile run (defaults documented in docs/tracking.md; exposed for the
/// leave-one-out validation, not per-record tuning).
struct ProfileRunConstants {
  double ambiguity_ratio = 0.5;        ///< OrderDiscoveryOptions::ambiguity_ratio for a profile file
  double target_prominence_db = 20.0;  ///< OrderDiscoveryOptions::target_prominence_db
  double false_alarm = 1e-3;           ///< OrderDiscoveryOptions::false_alarm
};
TrackSpeedResult track_speed_with_profile(const std::vector<double>& x, double fs_hz, const MachineProfile& profile,
                                          const ProfileRunConstants& constants = {});

/// Decimation factor that TrackSpeedOptions::decimate == 0 selects for input rate `fs_hz`.
size_t auto_decimation(const TrackSpeedOptions& options, double fs_hz);

/// Track the shaft speed in `x` (any unit) sampled at `fs_hz`.
/// Throws std::invalid_argument with the validation message on bad options or input
/// (empty or non-finite samples, record shorter than one window).
TrackSpeedResult track_speed(const std::vector<double>& x, double fs_hz,
                             const TrackSpeedOptions& options);

/// JSON figures: arrays t_s, speed_hz (null where lost), confidence, lost, below_min, and
/// a summary object (update_rate_hz, median_speed_hz, lost_fraction, stated_min_speed_hz,
/// latency_s, decimation, tracker_rate_hz, acquisitions, losses).
nlohmann::json to_json(const TrackSpeedResult& r);

/// Median of the valid (non-lost) speeds, Hz; NaN if none.
double median_speed_hz(const TrackSpeedResult& r);

/// Fraction of updates with lost == true; 0 if there are none.
double lost_fraction(const TrackSpeedResult& r);

}  // namespace amb::host
