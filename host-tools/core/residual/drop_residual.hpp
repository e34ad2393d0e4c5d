#pragma once
// The residual loop on a drop event (a capture: levitated pre-trigger history, then the
// amplifiers are cut and the rotor falls onto its auxiliary bearings).
//  * Levitated part (before the trigger): the steady-state loop of residual_loop.hpp on that
//    history (the effects that act while the AMBs work: pedestal, runout, amplifier lag,
//    rotor modes, saturation). No rest segment, so aux_bearing_offset is not testable there.
//  * Drop part (after the trigger): the Phase C drop model fitted to it (host-tools/core/fit/),
//    then the geometry of the contacts (drop_contact.hpp) and three candidates, each added
//    only when its predicted change of the signals exceeds the noise (and the model's own
//    unknowns) and kept only when no drop-part error rises and its own figure falls:
//      sensor_runout           spin-locked departure of the contact points from the clearance
//                              circles (beyond what the fitted unbalance makes by bending the
//                              shaft between the contacts); tells runout from unbalance at one
//                              speed; the levitated part's runout (its 2x; the 1x is not unique
//                              there) and this one are subtracted from the drop readings
//      aux_bearing_offset      contact circles off the model's centres (bias-corrected by the
//                              fitted simulation), refitted
//      aux_support_compliance  contact deflection growing with the contact force at one
//                              bearing beyond the contact law and beyond the other bearing
//    What is left (drop spectra off the model per plane and band, spin-locked contact
//    residuals not added, a compliance asymmetry not added) is reported as unexplained.
// Nothing here reads declared faults or knows which effect a record carries.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "host-tools/core/fit/drop_measurement.hpp"
#include "host-tools/core/residual/drop_contact.hpp"
#include "host-tools/core/events/loaded_event.hpp"
#include "host-tools/core/residual/residual_loop.hpp"

namespace amb::host::residual {

struct DropResidualOptions {
  /// Progress lines (stage names, the drop fits' own lines), stderr in the command; null: silent.
  std::function<void(const std::string&)> progress;
  double window_s = 0.4;            ///< drop window compared after the trigger, s
  double min_levitated_s = 1.0;     ///< shortest pre-trigger history the steady loop is run on, s
  double orbit_error_window_s = 0.015; ///< time-domain orbit error over the first this-many s after the trigger (the Phase C cost's orbit window: free fall and first impacts; later bouncing is chaotic), s
  double contact_band = 0.9;        ///< a sample is a contact point when its radius about the centre >= this x clearance
  double contact_trim_sigma = 3.0;  ///< contact-circle fit: samples beyond this many robust scales of the radial residual's median are flight, left out
  double decorrelation_s = 1e-3;    ///< contact points closer than this in time count as one (uncertainty, BIC), s
  /// Smallest centre offset reported as evidence, fraction of the clearance: the measured
  /// contact circles of clean generated drops sit 10-18 um low (the flexible shaft sags
  /// between the aux contacts, not between the AMBs, and the straight-line sensor view reads
  /// that as a centre shift), so below 5 % of c an offset is not told from it.
  double min_offset_fraction = 0.05;
  /// Smallest probe gain ratio claimed, |ln(g1 / g2)| (a contact circle read as an ellipse): 1
  double min_gain_log_ratio = 0.02;
  /// Fixed-point refinements of the aux-bearing offset (each a drop-model refit) while the refitted
  /// simulation's contact circles stay > 2 standard errors off the measured ones
  int max_offset_iterations = 2;
  /// Fit the drop part with the board's rotor structure only (off: the drop cost chooses rigid
  /// or flexible, and a rigid choice gets the flexible rotor's sag bias added to its contact
  /// circles; on the main job's drop the flexible drop model fitted far worse, cost 14 vs 2.7)
  bool board_rotor_structure = false;
  double max_spin_accel_rad_s2 = 1e5; ///< a recorded speed changing faster than this is not the spin (a lost tracker, a command), rad/s^2
  double spin_locked_factor = 1.25; ///< a 1x contact residual is runout only above this x the fitted unbalance's contact signature (margin for its pinned-beam approximation)
  bool update_contact_law = false;  ///< fit the drop model with each contact law (rigid, hertz, linear) and keep the best (model updating; off by default: triples the drop part's time and, with the present fit, gains nothing)
  LoopOptions loop;                 ///< the steady loop on the levitated part
};

/// Centre of one aux bearing's clearance circle from the contact points of an orbit.
struct ContactCircle {
  bool valid = false;               ///< enough contact points (>= 20 decorrelated)
  std::array<double, 2> centre_m{}; ///< (x, y) in the sensor frame, m
  double radius_m = 0.0;            ///< effective contact radius (clearance + mean deflection), m
  double sigma_m = 0.0;             ///< standard error of each centre coordinate, m
  double misfit_rms_m = 0.0;        ///< rms of (|p - centre| - radius) over the contact points, m
  int points = 0;                   ///< contact points used
};

/// Fit a circle (centre and effective radius) per bearing to the aux-plane orbit points of
/// the sensor readings [A1, A2, B1, B2] (m, sampled at `fs_hz`) whose radius is at least
/// contact_band x clearance; starts from the rig's centres and clearances. Invalid when the
/// contact arc is too short to separate the centre from the radius.
std::array<ContactCircle, 2> estimate_contact_circles(const std::vector<std::array<double, 4>>& sensor_m,
                                                      const model::PlantParams& rig, double fs_hz,
                                                      const DropResidualOptions& o = {});

/// Radial scatter (standard deviation of |p - centre|) over the samples whose radius about
/// `centre` is at least contact_band x clearance, per bearing (m), and the number of them.
std::array<std::pair<double, int>, 2> contact_misfit(const std::vector<std::array<double, 4>>& sensor_m,
                                                     const model::PlantParams& rig,
                                                     const std::array<std::array<double, 2>, 2>& centre_m,
                                                     const DropResidualOptions& o = {});

/// Is the record a drop event: a trigger inside it, the coil currents near zero after it and
/// the orbit reaching the aux bearings. `why` receives the reason when not.
bool is_drop_event(const LoadedEvent& r, const board::BoardConfig& b, std::string* why = nullptr);

/// The drop part as the Phase C fit's measurement (20 ms before the trigger, `window_s` after).
fit::DropMeasurement drop_measurement_of(const LoadedEvent& r, const board::BoardConfig& b,
                                         const DropResidualOptions& o = {});

/// Error figures of the drop part, measurement against a fitted simulation.
struct DropErrors {
  ErrorFigures error;   ///< rms: orbit distance at the sensor planes over orbit_error_window_s / clearance;
                        ///< spectral, pearson: Welch PSDs of the four sensors after the trigger (1/3 octaves);
                        ///< statics: contact-circle misfit about the model's centres (bias-corrected) / clearance
  double cost = 0.0;    ///< Phase C cost at the fit
  double friction_coefficient = 0.0;
  std::array<ContactCircle, 2> measured_circle{}, simulated_circle{};
  std::array<std::array<double, 2>, 2> model_centre_m{};  ///< the model's aux-bearing centres, m
  double misfit_ssr_m2 = 0.0;   ///< sum of squared contact misfits about the bias-corrected model centres, m^2
  int misfit_points = 0;
  /// Measured minus simulated effective contact radius per bearing (valid circles only), m.
  std::array<double, 2> radius_excess_m{};
  std::array<std::vector<double>, 2> band_db;  ///< per sensor plane: measured / simulated PSD per band, dB (mean of the plane's sensors)
  std::vector<double> band_hz;                 ///< band centres, Hz
  double sag_scale = 0.0;   ///< the flexible rotor's sag bias added to a rigid model's circles, in weights (0: none added)
};

struct DropResidualOutcome {
  bool levitated_analysed = false;
  std::string levitated_note;                 ///< why not, when not
  ResidualOutcome levitated;                  ///< the steady loop on the pre-trigger history
  DropErrors drop_before, drop_after;
  std::vector<std::string> drop_notes;        ///< findings of the drop part
  std::vector<CandidateScore> drop_ranking;
  std::vector<EffectAdded> effects_added;     ///< levitated part first, then the drop part
  ErrorFigures before, after;                 ///< both parts: rms, spectral, statics = quadratic mean; pearson = mean
  std::string verdict;                        ///< "none", else added names joined with "+"
  std::string contact_law;                    ///< the drop model's contact law after model updating
  // Drop-part contact geometry (drop_contact.hpp).
  double angle_known_after_trigger_s = 0.0;   ///< how long after the trigger the rotor angle is known (speed record), s
  ContactRunout drop_runout;                  ///< all phasors free
  std::array<double, 2> runout_floor_m{};     ///< per sensor plane: the 1x level the fitted unbalance can make in contact (x spin_locked_factor), m
  model::effects::SensorRunout runout_applied;///< subtracted from the drop readings (zero: none)
  std::string runout_source;                  ///< "", "levitated", "drop", "levitated 2x + drop 1x"
  ContactCompliance compliance;               ///< force-deflection per bearing
  std::array<double, 2> gain_log_ratio_applied{}; ///< probe gain ratios ln(g1/g2) divided out of the drop readings (0: none)
  std::vector<UnexplainedItem> unexplained;   ///< levitated part's, then the drop part's (part = "drop")
};

/// Throws std::runtime_error naming the problem when the record is not a usable drop event.
DropResidualOutcome run_drop_residual(const LoadedEvent& r, const board::BoardConfig& b,
                                      const DropResidualOptions& o = {});

}  // namespace amb::host::residual
