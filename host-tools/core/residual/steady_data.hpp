#pragma once
// What the residual loop extracts from a steady-state record (levitated rotor at constant
// speed, optionally preceded by the rotor at rest on its auxiliary bearings):
//  * channels mapped to the board's 4 sensors and 4 actuator axes by position and angle,
//  * the rest segment (coil currents ~0 at the start) and its mean sensor readings,
//  * the steady window (speed within 0.5 % of its final value), the refined speed,
//  * per channel: static mean, complex phasors of speed orders 1..k_orders, and the Welch
//    PSD of what remains, on log-spaced bands (bands at speed orders left out).
#include <array>
#include <complex>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/loaded_event.hpp"

namespace amb::host::residual {

inline constexpr int k_channels = 8;  ///< [sensors A1, A2, B1, B2 (m); currents per actuator axis (A)]
inline constexpr int k_orders = 3;    ///< speed orders analysed

struct Band {
  double f_hz = 0.0;        ///< centre frequency, Hz
  double averages = 0.0;    ///< effective number of averaged periodogram values (chi^2 dof / 2)
  std::array<double, k_channels> psd{};  ///< one-sided PSD, unit^2/Hz
};

struct SteadyData {
  double fs_hz = 0.0;
  double spin_hz = 0.0;                 ///< refined speed in the steady window, Hz
  double window_s = 0.0;                ///< steady window length, s
  size_t window_start = 0, window_len = 0;
  std::array<double, k_channels> mean{};                     ///< static mean (m, A)
  std::array<double, k_channels> rms{};                      ///< RMS about zero of the window
  std::array<std::array<std::complex<double>, k_orders>, k_channels> order{}; ///< phasors at h*spin
  std::vector<Band> bands;
  bool has_rest = false;
  size_t rest_len = 0;
  std::array<double, 4> rest_mean_m{};  ///< sensor means at rest, m
  std::array<double, 4> rest_std_m{};   ///< their sample standard deviations, m
  std::array<std::vector<double>, k_channels> window;  ///< the steady window's samples
  std::vector<std::string> unmatched;   ///< record columns not matched to the rig
};

/// Options of the extraction.
struct SteadyOptions {
  double window_s = 2.0;        ///< steady window (the last this many seconds), s
  double segment_s = 0.25;      ///< Welch segment, s (resolution 1/segment_s)
  double f_min_hz = 8.0;        ///< lowest band, Hz
  double f_max_hz = 1500.0;     ///< highest band, Hz (clamped to 0.4 fs)
  int bands_per_octave = 8;
};

/// Where the rig's channels are in an event (host-tools/core/events matched them to the rig by
/// quantity, axial position and angle within the board's capture tolerances; a channel that
/// points the opposite way is already negated).
struct ChannelMap {
  std::array<const std::vector<double>*, k_channels> channel{};  ///< [sensors A1, A2, B1, B2 (m), currents per actuator axis (A)]
  const std::vector<double>* speed_hz = nullptr;                 ///< speed per sample, Hz; null: none
  std::vector<std::string> unmatched;   ///< event columns not matched to the rig
  const std::vector<double>& operator[](int c) const { return *channel[static_cast<size_t>(c)]; }
};

/// Throws std::runtime_error naming the first rig channel the event lacks.
ChannelMap match_channels(const LoadedEvent& r);

/// Throws std::runtime_error if the event lacks a channel the rig needs, or has no
/// steady window.
SteadyData extract_steady(const LoadedEvent& r, const board::BoardConfig& b, const SteadyOptions& o = {});

/// The remainder spectrum of samples [begin, begin + len) of d.window: mean and speed orders
/// 1..k_orders at d.spin_hz removed by least squares, Welch PSD (Hann, o.segment_s, 50 %
/// overlap), averaged over the 1/o.bands_per_octave bands from o.f_min_hz to
/// min(o.f_max_hz, 0.4 fs), bins within 2.5 bins of the first 8 speed orders left out (the
/// bands of extract_steady, which calls it on the whole window). Throws std::runtime_error
/// for samples beyond the window or fewer than one segment.
std::vector<Band> remainder_bands(const SteadyData& d, size_t begin, size_t len, const SteadyOptions& o);

/// Samples [begin, end) of an event (trigger index shifted; 0 if outside).
LoadedEvent slice_event(const LoadedEvent& r, size_t begin, size_t end);

}  // namespace amb::host::residual
