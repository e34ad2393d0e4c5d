#pragma once
// The end-to-end drop scenario on the simulated rig (the README's main job): levitate from
// the touchdown bearings, spin up, hold, cut the AMBs (a fault injected into the plant that
// the firmware is not told about), let the firmware detect it and enter the safe state, and
// let the rotor land and coast on its auxiliary bearings.
#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "firmware/board/board.hpp"

namespace amb::host {

struct DropScenarioOptions {
  std::string board = "bath-amb-rig";  ///< board name or path
  double hold_s = 1.5;                 ///< time at speed before the cut, s (longer than the board tracker's window, so its estimate at the cut is not a ramp average)
  double after_cut_s = 1.5;            ///< simulated time after the cut, s
  uint64_t noise_seed = 1;
  std::string out_dir = "amb-out";     ///< where the event, its export and the fit go
  bool fit = true;                     ///< run the Phase C fit on the captured drop
  bool residual = true;                ///< steady run with an undeclared effect + the residual loop
  /// The board's speed source for the run ("tracker": tachless, the board's STFT tracker;
  /// "tach", "command"; empty: the board file's). The tachometer stays wired either way: it
  /// feeds the tracker/tach disagreement diagnostic, and the capture records it in every
  /// sample (AMBE v3 `tach_hz`), so the event has the rotor's spin-down during the drop for
  /// Phase C whichever source stamps the board's speed estimate.
  std::string speed_source = "tracker";
  std::function<void(const std::string&)> progress;  ///< optional progress lines
};

/// One recorded instant (decimated) of the run, for plots and later phases.
struct ScenarioTrace {
  std::vector<double> t_s;
  std::vector<std::array<double, 2>> aux_x_m, aux_y_m;    ///< rotor centre at the aux planes (truth), m
  std::vector<std::array<double, 2>> contact_force_n;     ///< normal contact force per aux bearing, N
  std::vector<double> speed_hz;                           ///< rotor speed (truth), Hz
  std::vector<double> tracked_speed_hz;                   ///< the board's speed as its loop sees it, Hz (NaN: not tracked)
};

struct DropScenarioSummary {
  std::string board;
  bool levitated = false;
  double liftoff_s = 0.0;                 ///< time from the levitate command to "levitated", s
  bool reached_speed = false;
  double speed_at_cut_hz = 0.0;           ///< true rotor speed when the AMBs were cut, Hz
  std::string speed_source;               ///< the board's speed source in the run
  double tracked_speed_at_cut_hz = 0.0;   ///< board tracker's speed at the cut, Hz (NaN: lost or not running)
  double tracked_confidence_at_cut = 0.0; ///< its confidence, 0..1
  bool tracked_lost_at_cut = true;        ///< the tracker had no valid (fresh) speed at the cut
  uint64_t speed_disagreements = 0;       ///< tracker updates off the tachometer beyond the board's threshold
  double event_speed_at_trigger_hz = 0.0; ///< the stored event's speed stamp, Hz (NaN: lost)
  double event_speed_confidence = 0.0;    ///< its confidence as stored, 0..1
  bool event_speed_lost = true;           ///< the stored event says the speed was lost at the trigger
  double steady_orbit_max_m = 0.0;        ///< largest orbit radius at a sensor plane while at speed, m
  double aux_clearance_m = 0.0;           ///< smallest aux-bearing clearance, m
  double cut_time_s = 0.0;                ///< simulated time of the cut, s
  bool fault_detected = false;
  std::string fault_reason;               ///< firmware's reason for the safe state
  double detection_delay_ms = 0.0;        ///< cut -> safe state, ms
  double max_contact_force_n = 0.0;       ///< over both aux bearings after the cut, N
  double speed_end_hz = 0.0;              ///< rotor speed at the end of the run, Hz
  double friction_energy_j = 0.0;         ///< dissipated at the aux contacts, J
  std::string final_state;
  uint64_t loop_periods = 0;
  uint64_t loop_overruns = 0;
  double wall_s = 0.0;
  double simulated_s = 0.0;
  // Phase A/B: the captured event.
  bool event_captured = false;
  std::string event_path;                 ///< board event file (AMBE v3)
  std::string event_export_stem;          ///< measured-event export (CSV + JSON) of it
  std::string trigger_cause;
  double trigger_delay_ms = 0.0;          ///< cut -> capture trigger, ms
  std::string phase_b_fault;              ///< Phase B verdict
  double phase_b_confidence = 0.0;
  std::string phase_b_summary;
  // Phase C/E: the fit and the wear record.
  bool fitted = false;
  double friction_coefficient = 0.0;
  double fit_cost = 0.0;
  int fit_evaluations = 0;
  double fit_wall_s = 0.0;
  bool fit_converged = false;             ///< never true with a bound active
  double friction_uncertainty = 0.0;      ///< the fit's uncertainty of the friction coefficient, 1
  bool fit_bound_active = false;          ///< a fitted value sits on its bound
  int fit_rotor_modes_per_plane = 0;      ///< rotor structure the fit chose (2: rigid), modes per plane
  std::string contact_law;                ///< drop-model contact law used by the fit
  std::array<std::string, 2> whirl_direction{};  ///< measured whirl per aux bearing: none/bouncing/forward/backward
  std::array<double, 2> whirl_frequency_hz{};    ///< its mean whirl frequency, Hz
  std::array<double, 2> load_whirl_hz{};         ///< whirl of the fitted model's contact point (load map; + forward), Hz
  std::array<double, 3> rubbing_s{};      ///< swing, forward, backward (bearing 1), s
  std::string fit_error;                  ///< why the fit did not run, if it did not
  // Phase E and the report.
  bool wear_written = false;
  std::string wear_path;                  ///< wear record (AMBW v1) after this event
  uint32_t wear_sequence = 0;
  double wear_peak_force_n = 0.0;         ///< largest contact force in the fitted model, N
  double wear_friction_energy_j = 0.0;    ///< both bearings, this event, J
  std::array<int, 2> load_peak_bin_deg{};  ///< polar bin (deg from upward vertical) of the largest event load, per bearing
  std::array<double, 2> load_sum_n{};      ///< sum of contact forces over all bins, per bearing, N
  std::string report_path;                ///< the HTML report of the event
  // Closing the loop: a steady run at speed whose plant has an effect the host model lacks
  // (chosen here, in the generator; the residual loop reads only the written record).
  bool residual_ran = false;
  std::string residual_record;            ///< the steady record (measured-event sidecar)
  std::string residual_verdict;           ///< "none" or the effects added
  std::array<double, 3> residual_before{}, residual_after{};  ///< rms, spectral (dB), pearson
  std::string residual_error;
  // The same on a generated drop event (levitated history + drop) whose rig has an
  // aux-bearing centre offset nobody declared; errors: rms, spectral (dB), pearson, statics.
  bool drop_residual_ran = false;
  std::string drop_residual_record;
  std::string drop_residual_verdict;
  std::array<double, 4> drop_residual_before{}, drop_residual_after{};
  /// Each added element's parameters (name -> SI value), e.g. the found aux-bearing offsets.
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>> drop_residual_added;
  std::string drop_residual_error;
  ScenarioTrace trace;
};

/// Run it. Throws std::runtime_error (with what went wrong) if the board cannot be loaded.
DropScenarioSummary run_drop_scenario(const DropScenarioOptions& options);

}  // namespace amb::host
