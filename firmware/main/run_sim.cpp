#include <cmath>
#include <cstdio>

#include "firmware/budget/board_budget.hpp"
#include "firmware/budget/print_budget.hpp"
#include "firmware/main/run_modes.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "firmware/sil/sil_sweep.hpp"
#include "firmware/events/sweep_event.hpp"

namespace amb::fwmain {

namespace {

// --sweep: the board's sweep on its simulated rig (SilSweepBench: the firmware with its capture
// and event writer), levitated or at speed; prints the stored event's summary.
int run_sim_sweep(const board::BoardConfig& board, const RunOptions& opt) {
  std::printf("amb-firmware: board %s (%s), backend sim, loop %.0f Hz, loop-sensitivity sweep\n", board.name.c_str(),
              board.source.c_str(), board.rate_hz);
  sil::SilSweepBench bench(board);
  if (!bench.supervisor().sweep_config_error().empty()) {
    std::fprintf(stderr, "amb-firmware: sweep: %s\n", bench.supervisor().sweep_config_error().c_str());
    return 1;
  }
  std::string err;
  if (!bench.levitate(opt.spin, err)) {
    std::fprintf(stderr, "amb-firmware: %s\n", err.c_str());
    return 2;
  }
  std::printf("  t=%6.3f s  %s\n", bench.rig().time_s(), opt.spin ? "at speed" : "levitated");
  bench.supervisor().request_sweep_start();
  sil::SilSweepOptions so;
  so.progress = [](const fw::SweepStatus& s, double t) {
    std::printf("  t=%6.3f s  sweep %s, axis %d (%u of %u), period %u of %u\n", t, fw::to_string(s.state), s.axis,
                s.axis_index + 1u, static_cast<unsigned>(s.axes_total), s.period + 1, s.periods_per_axis);
  };
  const sil::SilSweepOutcome o = bench.run_sweep(3600.0, so);
  const fw::Status st = bench.supervisor().status();
  if (!o.stored) {
    std::fprintf(stderr, "amb-firmware: sweep: %s\n", o.error.c_str());
    return 2;
  }
  fw::SweepEvent e;
  if (!fw::decode_sweep_event(o.event_bytes, e, err)) {
    std::fprintf(stderr, "amb-firmware: sweep event: %s\n", err.c_str());
    return 2;
  }
  const double df = board.rate_hz / e.samples_per_period;
  std::printf("  t=%6.3f s  sweep event %s stored: %zu bytes, %zu axes, %zu lines %.4g .. %.4g Hz, amplitude %.4g A, "
              "crest factor %.3f%s%s\n", bench.rig().time_s(), o.event_name.c_str(), o.event_bytes.size(), e.axes.size(),
              e.bins.size(), e.bins.front() * df, e.bins.back() * df, e.amplitude_a, e.crest_factor,
              e.aborted ? ", ABORTED: " : "", e.aborted ? fw::to_string(e.abort_reason) : "");
  std::printf("  state %s, fault %s; sweeps started %u, completed %u, aborted %u, refused %u\n", fw::to_string(st.state),
              fw::to_string(st.fault), st.sweep.started, st.sweep.completed, st.sweep.aborts, st.sweep.refusals);
  return e.aborted ? 2 : 0;
}

}  // namespace

int run_sim(const board::BoardConfig& board, const RunOptions& opt) {
  if (opt.sweep) return run_sim_sweep(board, opt);
  sil::SilOptions so;
  so.paced = opt.paced;
  so.analysis = opt.analysis ? sil::SilAnalysis::thread : sil::SilAnalysis::off;
  sil::SilRig rig(board, so);
  fw::Supervisor& sup = rig.supervisor();
  const double hold_s = opt.duration_s >= 0.0 ? opt.duration_s : 1.0;
  std::printf("amb-firmware: board %s (%s), backend sim, loop %.0f Hz%s\n", board.name.c_str(),
              board.source.c_str(), board.rate_hz, opt.paced ? ", paced" : "");
  {
    // The buffers and storage this board needs on the board (the linux backend's set-up).
    fw::BudgetOptions bo;
    bo.analysis_thread = opt.analysis && board.tracker.enabled;
    fw::print_budget(stdout, fw::buffer_budget(board, bo), fw::storage_budget(board));
  }
  auto phase_is = [](fw::Phase p) { return [p](const fw::Status& s) { return s.phase == p || s.state == fw::State::fault; }; };

  sup.post(fw::Command::levitate);
  if (!rig.run_until(phase_is(fw::Phase::levitated), 10.0) || sup.state() == fw::State::fault) {
    std::fprintf(stderr, "amb-firmware: lift-off failed (%s)\n", fw::to_string(sup.status().fault));
    return 2;
  }
  std::printf("  t=%6.3f s  levitated\n", rig.time_s());
  if (opt.spin) {
    sup.post(fw::Command::run);
    if (!rig.run_until(phase_is(fw::Phase::at_speed), 600.0) || sup.state() == fw::State::fault) {
      std::fprintf(stderr, "amb-firmware: spin-up failed (%s)\n", fw::to_string(sup.status().fault));
      return 2;
    }
    std::printf("  t=%6.3f s  at speed %.1f Hz\n", rig.time_s(), sup.status().speed_command_hz);
  }
  rig.run_for(hold_s);
  if (rig.analysis() != nullptr && opt.analysis && !opt.paced) {
    // Unpaced, the simulation outruns the analysis thread (it polls in wall time): let it
    // analyse what the loop handed over before its result is read, and say how far behind it was.
    const sil::SilRig::AnalysisDrain d = rig.drain_analysis(30.0);
    std::printf("  analysis thread: %llu samples (%.2f s simulated) not yet analysed at t=%.3f s; caught up in %.3f s wall%s\n",
                static_cast<unsigned long long>(d.queued_before), d.behind_s, rig.time_s(), d.waited_s,
                d.queued_after == 0 ? "" : " -- FELL BEHIND: still not done after 30 s");
    rig.run_for(1.0 / board.rate_hz);  // one period: the loop takes the newest update
  }
  if (const fw::AnalysisTask* a = rig.analysis()) {
    const fw::Status s = sup.status();
    const fw::AnalysisStatus as = a->status();
    std::printf("  t=%6.3f s  speed source %s: estimate %.3f Hz (confidence %.2f%s), tracked %.3f Hz, plant %.3f Hz; "
                "tracker updates %llu, ring drops %llu, tach disagreements %llu\n",
                rig.time_s(), fw::to_string(board.tracker.speed_source), s.speed_estimate_hz, s.speed_confidence,
                s.speed_lost ? ", LOST" : "", s.tracked.speed_hz, rig.plant().outputs().spin_speed_hz,
                static_cast<unsigned long long>(as.tracker_updates), static_cast<unsigned long long>(as.ring_drops),
                static_cast<unsigned long long>(s.counters.speed_disagreements));
    if (as.defects_valid)
      std::printf("  bearing %s at the tracked speed: FTF %.2f Hz, BPFO %.2f Hz, BPFI %.2f Hz, BSF %.2f Hz\n",
                  board.bearing.monitored.c_str(), as.ftf_hz, as.bpfo_hz, as.bpfi_hz, as.bsf_hz);
  }
  sup.post(fw::Command::land);
  rig.run_until([](const fw::Status& s) { return s.state != fw::State::levitating && s.state != fw::State::running; }, 600.0);
  const fw::Status st = sup.status();
  const auto& ls = rig.loop().stats();
  std::printf("  t=%6.3f s  %s (fault: %s)\n", rig.time_s(), fw::to_string(st.state), fw::to_string(st.fault));
  std::printf("  loop: %llu periods, %llu overruns, read failures %llu, saturated steps %llu\n",
              static_cast<unsigned long long>(ls.periods), static_cast<unsigned long long>(ls.overruns),
              static_cast<unsigned long long>(st.counters.read_failures),
              static_cast<unsigned long long>(st.counters.saturated_steps));
  // The host's work per period (the simulated clock stands still in it) and the delay the
  // plant applies (the board's loop_delay_periods).
  std::printf("  loop delay: host work sample -> demand written p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us; "
              "plant applies %.2f periods (%.1f us)\n",
              static_cast<double>(ls.delay_quantile_ns(0.5)) * 1e-3, static_cast<double>(ls.delay_quantile_ns(0.99)) * 1e-3,
              static_cast<double>(ls.delay_quantile_ns(0.999)) * 1e-3, static_cast<double>(ls.max_delay_ns) * 1e-3,
              board.loop_delay_periods, board.loop_delay_periods / board.rate_hz * 1e6);
  return st.state == fw::State::inactive ? 0 : 2;
}

}  // namespace amb::fwmain
