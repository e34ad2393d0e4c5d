#pragma once
// Everything one event report shows. Every section is optional: a section is either filled
// (`data`) or carries the reason it is not available (`why_not`), which the report prints in
// a box instead of a plot. Nothing is ever drawn from made-up data.
//
// Conventions: times in s relative to the event's trigger sample; positions in m; polar
// angles in deg from the upward vertical, positive towards +x (board convention, the bottom
// of a bearing is 180 deg); forces in N.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace amb::host::report {

/// A section that may be missing, with the reason.
template <class T>
struct Section {
  std::optional<T> data;
  std::string why_not = "not computed";   ///< shown when data is empty: what is missing and how to get it
  std::string source;                      ///< where the data came from (shown under the plot)
  bool available() const { return data.has_value(); }
  void set(T value, std::string from) {
    data = std::move(value);
    source = std::move(from);
    why_not.clear();
  }
  void unavailable(std::string why) {
    data.reset();
    why_not = std::move(why);
  }
};

/// Key facts of the event (always shown as a table).
struct EventFacts {
  std::vector<std::pair<std::string, std::string>> rows;  ///< label, value
};

/// Orbit at one plane, with the clearance circle.
struct OrbitPlane {
  std::string name;                 ///< e.g. "bearing A"
  std::vector<double> sensor_x_m, sensor_y_m;  ///< rotor centre at the sensor plane, m
  std::vector<double> aux_x_m, aux_y_m;        ///< extrapolated to the aux-bearing plane (rigid rotor), m
  std::vector<double> t_s;                     ///< time of each sample from the trigger, s
  std::vector<double> truth_x_m, truth_y_m;    ///< simulated runs only: the plant's rotor centre at the aux plane after the trigger, m
  double clearance_m = 0.0;         ///< radial clearance of the aux bearing, m
};

/// Contact polar angle, its slope and the rubbing states of one bearing.
struct RubbingTrace {
  std::string name;                 ///< e.g. "bearing A"
  std::vector<double> t_s;
  std::vector<double> angle_deg;    ///< unwrapped whirl angle (counter-clockwise), deg
  std::vector<double> slope_hz;     ///< its slope, rev/s (= rad/s / 2 pi)
  std::vector<int> state;           ///< 0 none, 1 swing, 2 forward rub, 3 backward rub
  std::array<double, 3> durations_s{};  ///< swing, forward, backward, s
  std::vector<std::pair<std::string, std::string>> rows;  ///< the durations as quoted figures (name, value)
};

struct SpeedTrace {
  std::vector<double> t_s;
  std::vector<double> speed_hz;            ///< speed estimate, Hz
  std::string speed_label = "speed estimate";  ///< legend of speed_hz (a measured event's own speed channel is no estimate)
  std::vector<double> speed_command_hz;    ///< drive set-point, Hz (may be empty)
  std::vector<double> plant_speed_hz;      ///< the rig's tachometer (in SIL the plant's spin), Hz; NaN where none (may be empty)
  std::vector<uint8_t> not_tracked;        ///< 1: the board had no valid speed this sample (lost flag) (may be empty)
};

struct ForceTrace {
  std::vector<double> t_s;
  std::array<std::vector<double>, 2> normal_n;    ///< mean normal contact force per bearing, N
  std::array<std::vector<double>, 2> friction_n;  ///< friction force per bearing, N (may be empty)
};

/// Load over the circumference, one value per 1-degree bin (index = angle in deg).
struct LoadMap {
  std::array<std::vector<double>, 2> event_n;       ///< this event, per bearing (empty: not known)
  std::array<std::vector<double>, 2> cumulative_n;  ///< all events so far, per bearing (empty: not known)
};

struct FitConvergence {
  std::vector<double> cost_history;  ///< best cost after the design of experiments and each iteration
  double friction_coefficient = 0.0;
  bool converged = false;
  int evaluations = 0;
  double wall_s = 0.0;
  std::string stop_reason;
  std::vector<std::pair<std::string, double>> figures;  ///< extra label/value rows
  std::vector<std::pair<std::string, std::string>> rows;  ///< formatted rows (figures quoted from ReportData::figures)
};

/// Residual spectra of one channel: measured and the model after each step of the loop.
struct ResidualSpectra {
  std::string channel;                               ///< e.g. "sensor A1"
  std::vector<double> f_hz;
  std::vector<double> measured;                      ///< PSD, unit^2/Hz
  std::vector<std::pair<std::string, std::vector<double>>> model_steps;  ///< ("base model", psd), ("+ name", psd), ...
  std::string unit;                                  ///< "m^2/Hz" or "A^2/Hz"
  std::vector<std::pair<std::string, std::string>> figures;  ///< error figures before/after, verdict
};

/// Residual loop on a drop event: figures per part and the contact-circle centres.
struct DropResidualSummary {
  std::vector<std::pair<std::string, std::string>> rows;                    ///< verdict, errors before/after
  std::array<std::vector<std::pair<std::string, std::string>>, 2> bearing;  ///< per aux bearing: centres, uncertainty
};

struct WearSummary {
  std::vector<std::pair<std::string, std::string>> rows;        ///< record-wide facts
  std::array<std::vector<std::pair<std::string, std::string>>, 2> bearing;  ///< per bearing facts
};

/// The board's quick-look aux-bearing load of a drop (bearing task, AMBE v2), and whether the
/// host's fitted wear record supersedes it.
struct QuickLookSummary {
  std::vector<std::pair<std::string, std::string>> rows;                    ///< speed source, constants used
  std::array<std::vector<std::pair<std::string, std::string>>, 2> bearing;  ///< per aux bearing: peak force, angle, life fraction
  std::string superseded_by;   ///< empty: the quick-look is the newest estimate; else what replaces it
};

struct ReplayVerdict {
  std::vector<std::pair<std::string, std::string>> rows;
  bool reproduced = false;
};

/// A figure the page quotes (a peak force, a rubbing time): defined once, in the page's
/// "Figures" table with its definition, and quoted elsewhere under the same name with the same
/// value. Two definitions of one quantity (the board's quick-look vs the fitted model) are two
/// figures with two names, and the definition says why they differ.
struct Figure {
  std::string name;        ///< e.g. "peak contact force A, board quick-look"
  std::string value;       ///< formatted with its unit, e.g. "4182 N"
  std::string definition;  ///< what it is, from what, over which window
};

struct ReportData {
  std::string title;                     ///< page title
  std::string subtitle;                  ///< e.g. the event file
  std::string generated_by = "amb-host report";
  EventFacts facts;
  Section<std::vector<OrbitPlane>> orbit;
  Section<std::vector<RubbingTrace>> rubbing;
  Section<SpeedTrace> speed;
  Section<ForceTrace> forces;
  Section<LoadMap> load;
  Section<FitConvergence> fit;
  Section<std::vector<ResidualSpectra>> residual;
  Section<DropResidualSummary> drop_residual;
  Section<WearSummary> wear;
  Section<QuickLookSummary> quick_look;  ///< board quick-look load (AMBE v2 events)
  Section<ReplayVerdict> replay;
  std::vector<Figure> figures;           ///< each figure once (define_figure in report_builder.hpp)
  std::vector<std::string> cause_chain;  ///< what led to the event, in order (e.g. cut -> trigger -> fault -> safe state)
  std::vector<std::string> notes;        ///< shown at the end
};

}  // namespace amb::host::report
