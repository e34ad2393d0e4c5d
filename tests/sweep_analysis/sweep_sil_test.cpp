// The sweep analysis on the simulated rigs (no effect injected): a multisine at the default
// amplitude on each control axis of the Bath and Unicamp rigs (sweep_sil.hpp: the firmware's
// controller on the sim backend, the nonlinear penalty-contact plant, sensor noise on). The
// measured sensitivity peak agrees with the board's linearised prediction (exact discrete
// closed loop, model/analysis/closed_loop) within 5 %, and the coherence of S is >= 0.95 on every
// line of the swept band. The plant and the analysis share only the board file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "host-tools/core/sweep/sweep_analysis.hpp"
#include "host-tools/core/sweep/sweep_estimate.hpp"
#include "host-tools/core/sweep/sweep_model.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/sweep_analysis/sweep_sil.hpp"

using namespace amb;

namespace {

void check_rig(const char* name) {
  const board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/" + name + ".toml");
  test::SilSweepOptions o;
  const host::sweep::SweepRecord r = test::run_sil_sweep(b, o);
  const host::sweep::SweepEstimate e = host::sweep::estimate_sweep(r);
  std::vector<int> axes;
  for (const auto& a : r.axes) axes.push_back(a.axis);
  const host::sweep::SweepLoopModel m(b, 0.0, axes, r.plan.frequencies_hz);
  const double lo = r.plan.frequencies_hz.front(), hi = r.plan.frequencies_hz.back();
  for (size_t a = 0; a < e.axes.size(); ++a) {
    const auto& ax = e.axes[a];
    const auto mp = m.peak(a, lo, hi, {});
    // The model's largest |S| over the same lines (the measured peak is a line).
    double line_peak = 0.0;
    double err_db = 0.0;
    for (size_t l = 0; l < ax.lines.size(); ++l) {
      line_peak = std::max(line_peak, std::abs(m.board()[a][l].s));
      err_db += std::pow(20.0 * std::log10(std::abs(ax.lines[l].s.h) / std::abs(m.board()[a][l].s)), 2);
    }
    err_db = std::sqrt(err_db / ax.lines.size());
    std::printf("[ RESULT ] %s axis %d: measured peak %s; model peak %.3f at %.1f Hz (zone %s), model over the lines %.3f "
                "(%+.2f %%); S rms error %.2f dB; min S coherence %.4f over %zu lines %.0f-%.0f Hz, amplitude %.3f A "
                "(crest %.2f)\n",
                name, ax.axis, ax.peak.statement.c_str(), mp.peak, mp.frequency_hz, model::analysis::to_string(mp.zone),
                line_peak, 100.0 * (ax.peak.peak / mp.peak - 1.0), err_db, ax.min_coherence_s, ax.lines.size(), lo, hi,
                r.plan.amplitude_a, r.plan.crest_factor);
    ASSERT_TRUE(ax.peak.found);
    EXPECT_NEAR(ax.peak.peak, mp.peak, 0.05 * mp.peak) << name << " axis " << ax.axis;
    EXPECT_GE(ax.min_coherence_s, 0.95) << name << " axis " << ax.axis;
    EXPECT_EQ(ax.peak.zone, model::analysis::to_string(mp.zone));
  }
}

TEST(SweepSil, BathPeakMatchesTheLinearisedModel) { check_rig("bath-amb-rig"); }
TEST(SweepSil, UnicampPeakMatchesTheLinearisedModel) { check_rig("unicamp-amb-rig"); }

}  // namespace

namespace {

// A stepped-sine record (one line per step, the steps one after the other) through the same
// estimators: |S| at each step's line agrees with the board's model within 3 %.
TEST(SweepSil, SteppedSineThroughTheSameEstimators) {
  const board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig.toml");
  test::SilSweepOptions o;
  o.stepped = true;
  o.axes = {0};
  o.samples_per_period = 1000;
  o.lines = 6;
  o.f_lo_hz = 30.0;
  o.f_hi_hz = 600.0;
  o.recorded_periods = 4;
  const host::sweep::SweepRecord r = test::run_sil_sweep(b, o);
  ASSERT_EQ(r.plan.kind, host::sweep::ExcitationKind::stepped_sine);
  ASSERT_EQ(r.axes[0].excitation_a.size(), r.plan.frequencies_hz.size() * 4u * 1000u);
  const host::sweep::SweepEstimate e = host::sweep::estimate_sweep(r);
  const host::sweep::SweepLoopModel m(b, 0.0, {0}, r.plan.frequencies_hz);
  for (size_t l = 0; l < e.axes[0].lines.size(); ++l) {
    const auto& q = e.axes[0].lines[l];
    const double ms = std::abs(m.board()[0][l].s);
    std::printf("[ RESULT ] stepped sine %.0f Hz: |S| %.3f [%.3f, %.3f], model %.3f (%+.2f %%), coherence %.4f\n", q.f_hz,
                std::abs(q.s.h), q.s.mag_lo, q.s.mag_hi, ms, 100.0 * (std::abs(q.s.h) / ms - 1.0), q.s.coherence);
    EXPECT_NEAR(std::abs(q.s.h), ms, 0.03 * ms) << q.f_hz;
    EXPECT_GE(q.s.coherence, 0.95) << q.f_hz;
  }
}

// Too few recorded periods for the residual loop's noise weights: the zone is still rated, the
// loop is not run and the analysis says why; from the stated minimum on it runs.
TEST(SweepSil, ResidualLoopNeedsEnoughPeriods) {
  const board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig.toml");
  test::SilSweepOptions o;
  o.axes = {0};
  o.lines = 12;
  o.recorded_periods = 2;
  const host::sweep::SweepRecord few = test::run_sil_sweep(b, o);
  const host::sweep::SweepAnalysis a = host::sweep::analyse_sweep(few, b);
  EXPECT_FALSE(a.residual_done);
  ASSERT_EQ(a.zones.size(), 1u);
  EXPECT_TRUE(a.zones[0].measured.found);
  bool said = false;
  for (const std::string& n : a.notes) said = said || n.find("residual loop not run") != std::string::npos;
  EXPECT_TRUE(said);
  host::sweep::SweepAnalysisOptions ao;
  ao.min_residual_periods = 2;
  EXPECT_TRUE(host::sweep::analyse_sweep(few, b, ao).residual_done);
}

}  // namespace
