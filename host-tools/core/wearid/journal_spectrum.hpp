#pragma once
// The measured side of the wear identification (seed 002 section 2.5): the +1x and -1x
// full-spectrum components at the journal-bearing probes at one steady speed, referred to
// the key phasor, and the journal's static position from the probes' mean.
//
// Event requirements: two displacement channels at the board's journal plane, along the
// board's probe directions (matched within capture.match_*_tolerance), a speed channel or
// the speed at the trigger, and a key phasor: a `voltage` channel named "keyphasor", a
// once-per-revolution pulse whose leading edge is at spin angle 0 (its width is measured).
// The probes read the journal's displacement from the bore centre.
#include <array>
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/loaded_event.hpp"
#include "host-tools/core/wearid/rig_response.hpp"
#include "model/journal/reynolds_fvm.hpp"

namespace amb::host::wearid {

struct JournalMeasurement {
  double speed_hz = 0.0;                 ///< mean spin speed over the analysed window, Hz
  FullSpectrum spectrum;                 ///< +1x / -1x at the journal probes, m
  bool has_amb_planes = false;           ///< the event also has the four AMB sensor channels
  std::array<FullSpectrum, 2> amb_planes{}; ///< +1x / -1x at the AMB sensor planes [A1, A2], [B1, B2], m
  double noise_m = 0.0;                  ///< rms of the full-spectrum noise per component, m (from off-bins)
  /// +2x / -2x at the journal probes, m, referred to twice the spin angle:
  /// x' + j y' = ... + Z+2 e^{j 2 theta} + Z-2 e^{-j 2 theta} (the film's second-order response).
  FullSpectrum second_harmonic;
  double noise_2x_m = 0.0;               ///< rms of the full-spectrum noise per component around 2x, m (from off-bins)
  model::journal::JournalState journal;  ///< static journal centre from the bore centre (velocities 0), m
  double eccentricity = 0.0;             ///< |static position| / C
  double window_s = 0.0;                 ///< analysed (whole revolutions at the end of the record), s
  double available_s = 0.0;              ///< steady data after the trigger in the record, s (window_s <= this)
  int revolutions = 0;
};

/// Extract the journal measurement. `window_s` (> 0) caps the analysed time at the end of
/// the record. Throws std::invalid_argument naming what the event lacks.
JournalMeasurement measure_journal(const LoadedEvent& ev, const board::BoardConfig& board, double window_s = 2.0);

}  // namespace amb::host::wearid
