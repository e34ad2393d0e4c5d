#include "host-tools/core/scenario/drop_scenario.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "hal/sim/sim_rig.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/events/measured_event.hpp"
#include "host-tools/core/fit/drop_fit.hpp"
#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/replay/event_replay.hpp"
#include "host-tools/core/report/report_builder.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/scenario/steady_record.hpp"
#include "model/effects/effect_set.hpp"
#include "host-tools/core/report/report_html.hpp"
#include "host-tools/core/wear/wear_record_file.hpp"
#include "host-tools/core/wear/wear_update.hpp"

namespace amb::host {

DropScenarioSummary run_drop_scenario(const DropScenarioOptions& o) {
  const auto wall0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) { if (o.progress) o.progress(s); };
  board::BoardConfig board = board::load_board(o.board);
  if (o.speed_source == "tracker") board.tracker.speed_source = fw::SpeedSource::tracker;
  else if (o.speed_source == "tach") board.tracker.speed_source = fw::SpeedSource::tach;
  else if (o.speed_source == "command") board.tracker.speed_source = fw::SpeedSource::command;
  else if (!o.speed_source.empty()) throw std::runtime_error("speed source '" + o.speed_source + "': must be tracker, tach or command");
  if (board.tracker.speed_source == fw::SpeedSource::tracker && !board.tracker.enabled)
    throw std::runtime_error("board " + board.name + ": speed source tracker needs an enabled [tracker] table");
  DropScenarioSummary sum;
  sum.speed_source = fw::to_string(board.tracker.speed_source);
  sum.board = board.name;
  sum.aux_clearance_m = std::min(board.plant.aux[0].clearance_m, board.plant.aux[1].clearance_m);

  sil::SilOptions so;
  so.noise_seed = o.noise_seed;
  so.tachometer = true;  // the Bath rig measures rotor speed (seed 000, Fig. 9)
  so.analysis = sil::SilAnalysis::lockstep;  // the board's tracker and bearing task, deterministic
  sil::SilRig rig(board, so);
  fw::Supervisor& sup = rig.supervisor();
  // Phase A: the floating capture sees every loop sample; its event thread's work (Phase B,
  // storage) is done by polling the writer between loop periods here.
  auto capture = std::make_unique<fw::FloatingCapture>();
  fw::configure_capture(*capture, board);
  rig.set_sink(capture.get());
  hal::sim::MemoryStorage storage(256ull << 20);
  fw::EventWriter writer(*capture, storage, board);
  std::string event_name;
  fw::EventRecord event;
  writer.on_event = [&](const fw::EventRecord& r, const std::string& name, bool stored) {
    if (stored && event_name.empty()) {
      event_name = name;
      event = r;
    }
  };

  // Decimated trace: every 1 ms of simulated time.
  const int every = std::max(1, static_cast<int>(std::lround(board.rate_hz / 1000.0)));
  int count = 0;
  bool after_cut = false;
  rig.on_period = [&](const fw::Status& st) {
    const model::PlantTruth tr = rig.plant().truth();
    if (after_cut)
      for (double f : tr.contact_force_n) sum.max_contact_force_n = std::max(sum.max_contact_force_n, f);
    if (++count % every) return;
    sum.trace.t_s.push_back(rig.time_s());
    sum.trace.aux_x_m.push_back(tr.aux_x_m);
    sum.trace.aux_y_m.push_back(tr.aux_y_m);
    sum.trace.contact_force_n.push_back(tr.contact_force_n);
    sum.trace.speed_hz.push_back(rig.plant().outputs().spin_speed_hz);
    sum.trace.tracked_speed_hz.push_back(st.tracked.lost ? std::nan("") : st.tracked.speed_hz);
  };
  auto reached = [](fw::Phase p) {
    return [p](const fw::Status& s) { return s.phase == p || s.state == fw::State::fault; };
  };

  rig.run_for(0.05);  // resting on the touchdown bearings
  const double t_lev = rig.time_s();
  say("levitate: lift-off from the touchdown bearings");
  sup.post(fw::Command::levitate);
  sum.levitated = rig.run_until(reached(fw::Phase::levitated), 5.0) && sup.state() != fw::State::fault;
  sum.liftoff_s = rig.time_s() - t_lev;
  if (sum.levitated) {
    say(io::printf_text("levitated after %.3f s; spinning up to %.1f Hz", sum.liftoff_s, board.lifecycle.operating_speed_hz));
    sup.post(fw::Command::run);
    const double spin_s = board.lifecycle.operating_speed_hz / board.lifecycle.spin_accel_hz_per_s;
    sum.reached_speed = rig.run_until(reached(fw::Phase::at_speed), spin_s + 5.0) && sup.state() != fw::State::fault;
  }
  if (sum.reached_speed) {
    say(io::printf_text("at speed; holding %.2f s", o.hold_s));
    const double end = rig.time_s() + o.hold_s;
    while (rig.time_s() < end && sup.state() == fw::State::running) {
      rig.run_for(0.001);
      const fw::Status s = sup.status();
      sum.steady_orbit_max_m = std::max({sum.steady_orbit_max_m, s.orbit_radius_m[0], s.orbit_radius_m[1]});
    }
  }
  // The cut: all amplifier channels lose their output (seed 000: "AMBs switched off").
  sum.speed_at_cut_hz = rig.plant().outputs().spin_speed_hz;
  {
    const fw::Status cs = sup.status();
    sum.tracked_speed_at_cut_hz = cs.tracked.speed_hz;
    sum.tracked_confidence_at_cut = cs.tracked.confidence;
    sum.tracked_lost_at_cut = cs.tracked.lost;
  }
  sum.cut_time_s = rig.time_s();
  model::PlantFaults cut;
  cut.current_factor = {0.0, 0.0, 0.0, 0.0};
  rig.plant().set_faults(cut);
  after_cut = true;
  say(io::printf_text("t=%.3f s: AMB channels cut at %.1f Hz", sum.cut_time_s, sum.speed_at_cut_hz));
  sum.fault_detected = rig.run_until([](const fw::Status& s) { return s.state == fw::State::fault; }, 0.5);
  sum.detection_delay_ms = (rig.time_s() - sum.cut_time_s) * 1e3;
  sum.fault_reason = fw::to_string(sup.status().fault);
  if (sum.fault_detected) say(io::printf_text("safe state after %.1f ms", sum.detection_delay_ms) + " (" + sum.fault_reason + ")");
  // Long enough for the capture to record its post-trigger window and freeze it.
  const double after_s = std::max(o.after_cut_s, board.capture.post_trigger_s + 0.1);
  rig.run_for(std::max(0.0, sum.cut_time_s + after_s - rig.time_s()));
  while (writer.poll() > 0) {
  }

  const fw::Status st = sup.status();
  sum.final_state = fw::to_string(st.state);
  sum.speed_end_hz = rig.plant().outputs().spin_speed_hz;
  sum.friction_energy_j = rig.plant().truth().friction_dissipated_j;
  sum.loop_periods = rig.loop().stats().periods;
  sum.loop_overruns = rig.loop().stats().overruns;
  sum.speed_disagreements = st.counters.speed_disagreements;
  if (!event_name.empty()) {
    sum.event_speed_at_trigger_hz = event.meta.speed_at_trigger_hz;
    sum.event_speed_lost = event.has_analysis ? event.analysis.speed_lost_at_trigger : true;
    sum.event_speed_confidence = event.has_analysis ? event.analysis.speed_confidence_at_trigger : 0.0;
  }
  sum.simulated_s = rig.time_s();

  // The stored event: write it out, export it to the exchange format, report Phase B.
  if (!event_name.empty()) {
    std::filesystem::create_directories(o.out_dir);
    std::vector<uint8_t> bytes;
    std::string err;
    if (storage.read(event_name, bytes, err)) {
      sum.event_path = (std::filesystem::path(o.out_dir) / event_name).string();
      std::ofstream(sum.event_path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                            static_cast<std::streamsize>(bytes.size()));
      sum.event_captured = true;
      sum.trigger_cause = fw::to_string(event.meta.cause);
      sum.trigger_delay_ms = (static_cast<double>(event.meta.trigger_t_ns) * 1e-9 - sum.cut_time_s) * 1e3;
      if (event.has_diagnosis) {
        sum.phase_b_fault = fw::diag::to_string(event.diagnosis.type);
        sum.phase_b_confidence = event.diagnosis.confidence;
        sum.phase_b_summary = event.diagnosis.summary;
      }
      say("event " + sum.event_path + " (trigger " + sum.trigger_cause + "); Phase B: " + sum.phase_b_fault);
      sum.event_export_stem = (std::filesystem::path(o.out_dir) / std::filesystem::path(event_name).stem()).string();
      export_measured_event(load_event(sum.event_path), sum.event_export_stem);
    }
  }
  // Phase C: fit the drop model to the captured drop (the fit reads only the export).
  std::unique_ptr<fit::DropFitResult> fitted;
  if (o.fit && sum.event_captured) {
    try {
      say("Phase C: fitting the drop model to the event (implicit filtering)");
      const std::string json = sum.event_export_stem + ".json";
      const fit::DropMeasurement m = fit::drop_measurement_from_event(load_event(json));
      fit::DropFitOptions fo;
      const fit::DropFitResult r = fit::fit_drop(m, board, fo);
      sum.fitted = true;
      sum.friction_coefficient = r.friction_coefficient;
      sum.fit_cost = r.cost.total;
      sum.fit_evaluations = r.evaluations;
      sum.fit_wall_s = r.wall_s;
      sum.fit_converged = r.converged;
      sum.friction_uncertainty = r.friction_uncertainty;
      sum.fit_bound_active = r.bound_active;
      sum.fit_rotor_modes_per_plane = r.rotor_modes_per_plane;
      sum.contact_law = r.contact_law;
      for (size_t b = 0; b < 2; ++b) {
        sum.whirl_direction[b] = r.whirl[b].direction;
        sum.whirl_frequency_hz[b] = r.whirl[b].frequency_hz;
      }
      sum.rubbing_s = {r.rubbing[0].swing_s, r.rubbing[0].forward_s, r.rubbing[0].backward_s};
      fitted = std::make_unique<fit::DropFitResult>(r);
    } catch (const std::exception& e) {
      sum.fit_error = e.what();
    }
  }
  // Phase E: the load over each bearing's circumference from the fitted contact forces,
  // accounted into the board's wear record (a fresh record here: first event).
  fw::WearRecord wear;
  if (fitted) {
    fw::WearRecord previous;
    previous.board_name = board.name;
    const wear::WearAccounting we = wear::account_drop(previous, fitted->trace.contact_steps, fitted->rubbing,
                                                       fitted->friction_coefficient, board.name, wear::wall_clock_unix_s(),
                                                       wear::WearOptions{});
    wear = we.record;
    sum.wear_path = (std::filesystem::path(o.out_dir) / "wear_record.ambw").string();
    wear::write_wear_record_file(sum.wear_path, wear);
    sum.wear_written = true;
    sum.wear_sequence = wear.sequence;
    sum.wear_peak_force_n = std::max(wear.bearing[0].peak_force_n, wear.bearing[1].peak_force_n);
    sum.wear_friction_energy_j = wear.bearing[0].friction_energy_j + wear.bearing[1].friction_energy_j;
    for (size_t b = 0; b < 2; ++b) {
      const auto& load = wear.bearing[b].event_load_n;
      sum.load_peak_bin_deg[b] = static_cast<int>(std::max_element(load.begin(), load.end()) - load.begin());
      for (float f : load) sum.load_sum_n[b] += f;
      sum.load_whirl_hz[b] = we.event.load[b].whirl_hz;
    }
  }
  // Close the loop with a steady run whose plant carries sensor runout (speed-locked: 1x at plane A,
  // 2x at plane B) that neither the firmware nor the host model is told about.
  std::unique_ptr<residual::SteadyData> steady_data;
  std::unique_ptr<residual::ResidualOutcome> residual_outcome;
  std::unique_ptr<residual::DropResidualOutcome> drop_residual_outcome;
  if (o.residual) {
    try {
      say("steady run with an undeclared effect; residual loop on its record");
      model::effects::EffectSet hidden;
      model::effects::SensorRunout r;
      r.r_m[0][0] = {6e-6, 3e-6};  // plane A, 1x
      r.r_m[1][1] = {0.0, 4e-6};   // plane B, 2x
      hidden.runout = r;
      SteadyRecordOptions so_steady;
      so_steady.board = o.board;
      sum.residual_record = generate_steady_record(o.out_dir, "steady_run", hidden, so_steady);
      // The code under test: the record in, the loop's outcome out.
      const auto rec = load_event(sum.residual_record);
      const board::BoardConfig rb = board::load_board(rec.board);
      const auto steady = residual::extract_steady(rec, rb);
      const auto out = residual::run_residual_loop(steady, rb);
      sum.residual_ran = true;
      sum.residual_verdict = out.verdict;
      sum.residual_before = {out.before.error.rms, out.before.error.spectral, out.before.error.pearson};
      sum.residual_after = {out.after.error.rms, out.after.error.spectral, out.after.error.pearson};
      steady_data = std::make_unique<residual::SteadyData>(steady);
      residual_outcome = std::make_unique<residual::ResidualOutcome>(out);
    } catch (const std::exception& e) {
      sum.residual_error = e.what();
    }
    // A drop event whose rig's aux-bearing centres are off the board's values (chosen here);
    // the loop sees a drop event, fits the drop model and reads the contact geometry.
    try {
      say("drop event with an undeclared effect; residual loop on it");
      model::effects::EffectSet hidden;
      model::effects::AuxBearingOffset a;
      a.x_m = {50e-6, -40e-6};
      a.y_m = {-60e-6, 30e-6};
      hidden.aux_offset = a;
      SteadyRecordOptions so_drop;
      so_drop.board = o.board;
      so_drop.drop_s = 0.4;
      sum.drop_residual_record = generate_steady_record(o.out_dir, "drop_run", hidden, so_drop);
      const auto rec = load_event(sum.drop_residual_record);
      const auto out = residual::run_drop_residual(rec, board::load_board(rec.board));
      sum.drop_residual_ran = true;
      sum.drop_residual_verdict = out.verdict;
      sum.drop_residual_before = {out.before.rms, out.before.spectral, out.before.pearson, out.before.statics};
      sum.drop_residual_after = {out.after.rms, out.after.spectral, out.after.pearson, out.after.statics};
      for (const auto& e : out.effects_added) sum.drop_residual_added.emplace_back(e.name, e.parameters);
      drop_residual_outcome = std::make_unique<residual::DropResidualOutcome>(out);
    } catch (const std::exception& e) {
      sum.drop_residual_error = e.what();
    }
  }
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  // The report: one self-contained HTML page for the event.
  if (sum.event_captured) {
    try {
      report::ReportData d = report::new_report_data("Drop event on " + board.name + " (SIL scenario)");
      report::add_event(d, event, board, sum.event_path);
      // Replay the stored event through a fresh firmware: the report shows whether the
      // controller outputs, triggers and Phase B are reproduced bit for bit.
      // The event names its board file (tach source there): the replay feeds the recorded
      // speed as the tachometer, so a tracker-stamped event replays bit for bit too.
      report::add_replay(d, replay::replay_event(event, board::load_board(o.board)));
      report::add_scenario_trace(d, sum);
      if (fitted) report::add_fit(d, *fitted, sum.event_export_stem + ".json");
      if (sum.wear_written) report::add_wear_record(d, wear, sum.wear_path);
      if (residual_outcome) report::add_residual(d, *steady_data, *residual_outcome, sum.residual_record);
      if (drop_residual_outcome)
        report::add_drop_residual(d, *drop_residual_outcome,
                                  sum.drop_residual_record + " (a generated drop event, not this one: its rig carries an "
                                                             "aux-bearing offset the loop is not told about)");
      sum.report_path = report::write_event_report(d, (std::filesystem::path(o.out_dir) /
                                                       (std::filesystem::path(sum.event_path).stem().string() + ".html")).string());
    } catch (const std::exception& e) {
      say(std::string("report not written: ") + e.what());
    }
  }
  return sum;
}

}  // namespace amb::host
