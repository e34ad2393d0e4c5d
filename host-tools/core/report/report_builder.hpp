#pragma once
// Fill a ReportData from whatever exists. Each add_* fills the sections its producer feeds
// and leaves the others alone; new_report_data() starts every section as "not available"
// with the reason and what to do about it, so a section whose producer is missing (or was
// not run) says so instead of showing anything made up.
//
// Producers: the board event (AMBE v1: facts, orbits, measured rubbing states, speed), the
// replay (host-tools/core/replay), the Phase C fit (host-tools/core/fit: convergence and its
// Phase D record of the fitted drop model), a Phase D record on its own (model/drop:
// contact forces; Phase E load map via host-tools/core/wear/load_map), the wear record
// (firmware/wear AMBW: cumulative load, durations, life), the residual loop
// (host-tools/core/residual: spectra before/after) and the SIL drop scenario's trace.
#include <array>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "firmware/events/event_record.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "host-tools/core/report/report_data.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/scenario/drop_scenario.hpp"
#include "model/drop/drop_simulation.hpp"

namespace amb::host::report {

/// Every section "not available" with the default reason; `title` for the page.
ReportData new_report_data(const std::string& title);

/// Defines (or redefines) the figure `name`; returns the value, for the section quoting it.
const std::string& define_figure(ReportData& d, const std::string& name, const std::string& value, const std::string& definition);

/// Facts, orbits at both bearing planes (sensor plane and extrapolated aux plane, with the
/// clearance circle), contact angle/slope/rubbing states from the measured orbit after the
/// trigger (model/drop/rubbing_states), speed. `source`: file name shown in the report.
void add_event(ReportData& d, const fw::EventRecord& e, const board::BoardConfig& board, const std::string& source);

/// Orbits at both planes (sensor plane, and the aux plane by rigid extrapolation, with the
/// clearance circle), the rubbing states from the trigger on and the largest aux-plane radius.
/// `r_m`: per sample the four sensor readings [A1, A2, B1, B2] along their own directions, m;
/// `trig`: trigger sample; `rate_hz`: sample rate, Hz; `spin_sign`: +1 spin counter-clockwise
/// seen from the board's reference end, -1 clockwise; `source`: shown under the plots.
/// add_event calls it for board events, add_loaded_event (report_measured.hpp) for measured ones.
void add_orbits(ReportData& d, const board::BoardConfig& board, const std::vector<std::array<double, 4>>& r_m, size_t trig,
                double rate_hz, double spin_sign, const std::string& source);

/// The replay verdict (amb-host replay).
void add_replay(ReportData& d, const replay::ReplayResult& r);

/// Phase D record of a drop-model run: contact forces and this event's load map (Phase E
/// binning, host-tools/core/wear/load_map). `what`: e.g. "fitted drop model".
void add_drop_trace(ReportData& d, const model::drop::DropTrace& t, const std::string& what);

/// Phase C fit: convergence and its Phase D record (add_drop_trace).
void add_fit(ReportData& d, const fit::DropFitResult& f, const std::string& source);

/// Wear record: summary and cumulative load per bearing (keeps this event's load if set).
void add_wear_record(ReportData& d, const fw::WearRecord& w, const std::string& source);

/// Residual loop on a steady-state record: measured spectra and the model before and after
/// the added effects, per sensor channel, with the error figures.
void add_residual(ReportData& d, const residual::SteadyData& data, const residual::ResidualOutcome& o,
                  const std::string& source);

/// Residual loop on a drop event: verdict, added elements, errors of both parts before and
/// after, the contact-circle centres per aux bearing.
void add_drop_residual(ReportData& d, const residual::DropResidualOutcome& o, const std::string& source);

/// The SIL drop scenario's trace (simulated truth): contact forces and speed after the cut.
void add_scenario_trace(ReportData& d, const DropScenarioSummary& s);

}  // namespace amb::host::report
