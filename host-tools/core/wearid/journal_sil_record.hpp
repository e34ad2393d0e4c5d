#pragma once
// Steady-speed records of the UNICAMP rig with a (possibly worn) journal bearing, generated
// in software-in-the-loop: the firmware levitates the rotor, places the journal at the
// static eccentricity and spins it to the speed; the plant carries the journal film (see
// model/journal/journal_rig.hpp) and noisy probes. Written in the measured-event exchange
// format with the journal probes and a key phasor, the way a DAQ export would be.
//
// This is the data generator of the wear-identification checks: it knows the wear it puts
// into the plant; the identification (wear_identification.hpp) only ever reads the files.
#include <cmath>
#include <cstdint>
#include <string>

#include "model/journal/journal_rig.hpp"
#include "model/journal/wear_geometry.hpp"

namespace amb::host::wearid {

struct JournalSilOptions {
  std::string board = "unicamp-journal-rig";  ///< board name or path (needs [journal_bearing])
  double eccentricity = 0.1;                  ///< static eccentricity ratio the AMBs hold
  model::journal::WearParams wear;            ///< wear put into the plant
  double speed_hz = 34.0;                     ///< steady speed, Hz
  double settle_s = 60.0;                     ///< wait at speed before recording, s (the integral action is slow: KP/KI = 10 s; the journal is within 0.06 % of the placement after 45 s, 0.01 % after 60 s)
  double relinearise_s = 2.0;                 ///< after the settle: re-linearise the film about the journal's actual mean position and settle this long, s (0: keep the placement point's coefficients)
  double record_s = 2.0;                      ///< recorded time, s
  std::uint64_t noise_seed = 1;
  /// Full Reynolds film in the plant (RotorAmbPlant::set_journal_film) from this long before
  /// the end of the settle on (s; 0: the linear element only, the default). The linear
  /// element is exact to first order only: at e = 0.7 the unbalance orbit (~17 um forward,
  /// ~7 um backward against a ~52 um minimum film) makes the real film add 2x components of
  /// ~0.3-0.7 um and move the 1x by ~10 %. One Reynolds solve per loop period (~0.1 ms).
  double full_film_s = 0.0;
  /// Film grid refined at the static journal position (the placement point, with the wear)
  /// until the estimated K/C error is below this (relative, model/journal/
  /// film_grid_refinement.hpp); the plant's film uses that grid. 0 (the library's default):
  /// the board's grid. `amb-host journal-sil` defaults to 0.002 (--grid-tolerance).
  double grid_tolerance = 0.0;
  /// Another film model for the plant's linear film element (placement and re-linearisation;
  /// not with full_film_s > 0): records the project's own film solver did not make (the
  /// independent finite-difference solver of tests/journal). Empty: the board's solver.
  model::journal::FilmCoefficientsFn film;
};

struct JournalSilSummary {
  bool ok = false;                  ///< levitated, reached speed, no fault
  std::string message;              ///< why not, when !ok
  double speed_hz = 0.0;            ///< plant speed at the end, Hz
  double static_eccentricity = 0.0; ///< journal's mean position / C over the record (truth)
  double orbit_peak_m = 0.0;        ///< peak journal excursion from its mean (truth), m
  double journal_clearance_m = 0.0;
  double sim_s = 0.0;               ///< simulated time, s
  int grid_theta = 0, grid_axial = 0;  ///< film grid the plant used
  double grid_error_estimate = NAN;    ///< its estimated relative K/C error (NaN: not refined, the board's grid)
  bool grid_converged = false;         ///< the tolerance was reached within the grid limits
};

/// Run the SIL and write STEM.csv / STEM.json. Throws std::runtime_error on I/O errors and
/// std::invalid_argument for a board without a journal bearing.
JournalSilSummary record_journal_sil(const JournalSilOptions& o, const std::string& stem);

}  // namespace amb::host::wearid
