// The loop-sensitivity sweep, board side (issue 35): the multisine period (its lines are the
// configured bins and nothing else; the crest factor it states), the [sweep] board keys, the
// generator's refusals and aborts, the record it hands over, the `sweep` event codec (round
// trip, corruption named, old drop files unaffected), the CAN status frame, and the proof that
// the control step with the generator running does not allocate.
#include "tests/firmware/alloc_counter.hpp"  // the counter is defined in supervisor_test.cpp

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "firmware/app/supervisor.hpp"
#include "firmware/common/crc32.hpp"
#include "firmware/board/board.hpp"
#include "firmware/budget/board_budget.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/sweep_event.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "firmware/sweep/multisine.hpp"
#include "firmware/sweep/sweep_generator.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb::fw;

namespace {

std::string board_text(const std::string& name) {
  std::ifstream f(std::string(amb::test::source_dir()) + "/boards/" + name + ".toml");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// DFT of one period of the table, bin k (plain sum, independent of the design's cosines).
std::complex<double> dft(const std::vector<float>& x, uint32_t k) {
  std::complex<double> s = 0.0;
  const double n = static_cast<double>(x.size());
  for (size_t i = 0; i < x.size(); ++i)
    s += static_cast<double>(x[i]) * std::exp(std::complex<double>(0.0, -2.0 * std::numbers::pi * k * static_cast<double>(i) / n));
  return s;
}

TEST(Multisine, LinesAreExactlyTheConfiguredBinsAndCrestIsAsStated) {
  const double rate = 10000.0;
  const uint32_t n = 2000;
  MultisineDesign d;
  ASSERT_EQ(design_multisine(rate, n, 20.0, 1500.0, 40, d), "");
  ASSERT_EQ(d.table.size(), n);
  ASSERT_GE(d.bins.size(), 30u);
  EXPECT_EQ(d.bins.front(), 4u);    // 20 Hz at 5 Hz bins
  EXPECT_EQ(d.bins.back(), 300u);   // 1500 Hz
  std::vector<bool> excited(n / 2 + 1, false);
  for (uint32_t k : d.bins) excited[k] = true;
  double line_min = 1e300, line_max = 0.0, other_max = 0.0;
  for (uint32_t k = 0; k <= n / 2; ++k) {
    const double m = std::abs(dft(d.table, k));
    if (excited[k]) {
      line_min = std::min(line_min, m);
      line_max = std::max(line_max, m);
    } else {
      other_max = std::max(other_max, m);
    }
  }
  // Equal lines, nothing between them (float table: ~1e-7 relative).
  std::printf("[ RESULT ] multisine N %u, %zu lines: line magnitude %.6g .. %.6g, largest other bin %.3g (%.2g of a line)\n",
              n, d.bins.size(), line_min, line_max, other_max, other_max / line_min);
  EXPECT_LT((line_max - line_min) / line_max, 1e-5);
  EXPECT_LT(other_max, 1e-5 * line_min);
  // Crest factor from the table itself (peak / rms), as stated, and low (Schroeder phases;
  // a single sine is 1.414, random phases over 30+ lines typically 3 or more).
  double peak = 0.0, sq = 0.0;
  for (float v : d.table) {
    peak = std::max(peak, std::abs(static_cast<double>(v)));
    sq += static_cast<double>(v) * v;
  }
  const double crest = peak / std::sqrt(sq / n);
  std::printf("[ RESULT ] crest factor stated %.4f, from the table %.4f\n", d.crest_factor, crest);
  EXPECT_NEAR(d.crest_factor, crest, 1e-5 * crest);
  EXPECT_NEAR(peak, 1.0, 1e-7);
  EXPECT_LT(d.crest_factor, 2.5);
  // A band with no bin is refused.
  EXPECT_NE(design_multisine(rate, n, 1.0, 4.0, 10, d), "");
}

TEST(SweepBoardKeys, ValidatedWithKeyAndRange) {
  const std::string text = board_text("bath-amb-rig");
  const amb::board::BoardConfig b = amb::board::parse_board(text, "bath");
  EXPECT_TRUE(b.sweep.enabled);
  EXPECT_EQ(b.sweep.samples_per_period, 10000u);  // default: a 1 s period at the board's rate
  auto refused = [&](const std::string& table, const std::string& key) {
    try {
      amb::board::parse_board(text + "\n[sweep]\n" + table, "test.toml");
      ADD_FAILURE() << "accepted " << table;
    } catch (const amb::board::BoardError& e) {
      std::printf("[ RESULT ] [sweep] %s-> %s\n", table.c_str(), e.what());
      EXPECT_EQ(e.key().rfind(key, 0), 0u) << e.what();  // the key, or an element of it
    }
  };
  refused("amplitude_fraction = 0.5\n", "sweep.amplitude_fraction");  // above the default limit 0.25
  refused("amplitude_limit_fraction = 0.05\namplitude_fraction = 0.1\n", "sweep.amplitude_fraction");
  refused("samples_per_period = 8\n", "sweep.samples_per_period");
  refused("f_max_hz = 6000.0\n", "sweep.f_max_hz");
  refused("samples_per_period = 100\nf_min_hz = 10.0\nf_max_hz = 50.0\n", "sweep.f_max_hz");  // no 100 Hz bin in the band
  refused("abort_clearance_fraction = 0.9\n", "sweep.abort_clearance_fraction");  // beyond the fault radius
  refused("axes = [0, 0]\n", "sweep.axes");
  refused("axes = [4]\n", "sweep.axes");
  refused("lines = 0\n", "sweep.lines");
  refused("recorded_periods = 0\n", "sweep.recorded_periods");
  refused("bogus = 1\n", "sweep.bogus");
  const amb::board::BoardConfig ok =
      amb::board::parse_board(text + "\n[sweep]\nsamples_per_period = 1000\naxes = [2, 0]\namplitude_fraction = 0.2\n", "t");
  EXPECT_EQ(ok.sweep.samples_per_period, 1000u);
  EXPECT_EQ(ok.sweep.axis_count(), 2u);
  EXPECT_TRUE(ok.sweep.axes[0] && ok.sweep.axes[2] && !ok.sweep.axes[1]);
}

TEST(SweepGenerator, AmplitudeAboveTheLimitIsRefused) {
  SweepParams p;
  p.amplitude_fraction = 0.3;
  p.amplitude_limit_fraction = 0.25;
  SweepGenerator g;
  const std::string err = g.configure(p, 10000.0, 2.5, 0.2e-3);
  EXPECT_NE(err.find("exceeds the limit"), std::string::npos) << err;
  EXPECT_EQ(g.config_refusal(), SweepRefusal::amplitude_limit);
  g.request_start();
  SweepInputs in;
  in.levitated = true;
  int axis = 0;
  EXPECT_EQ(g.begin_step(in, axis), 0.0);
  EXPECT_EQ(axis, -1);
  EXPECT_EQ(g.status().refusals, 1u);
  EXPECT_EQ(g.status().last_refusal, SweepRefusal::amplitude_limit);
  EXPECT_EQ(g.status().started, 0u);
}

// A small plan driven by hand: refusals by state, the settle/record schedule, the record's
// content, the abort on the orbit, the hand-over and release.
TEST(SweepGenerator, ScheduleRecordAbortAndHandOver) {
  SweepParams p;
  p.samples_per_period = 100;
  p.f_min_hz = 100.0;
  p.f_max_hz = 2000.0;
  p.lines = 8;
  p.settle_periods = 2;
  p.recorded_periods = 3;
  p.axes = {true, false, true, false};
  p.amplitude_fraction = 0.1;
  SweepGenerator g;
  ASSERT_EQ(g.configure(p, 10000.0, 2.0, 1e-4), "");
  EXPECT_DOUBLE_EQ(g.amplitude_a(), 0.2);
  SweepInputs in;
  int axis = 0;
  // Not levitated, then in fault: refused with the reason.
  g.request_start();
  g.begin_step(in, axis);
  EXPECT_EQ(g.status().last_refusal, SweepRefusal::not_levitated);
  in.fault = true;
  g.request_start();
  g.begin_step(in, axis);
  EXPECT_EQ(g.status().last_refusal, SweepRefusal::fault);
  EXPECT_EQ(g.status().refusals, 2u);
  in.fault = false;
  in.levitated = true;
  g.request_start();
  int periods_seen = 0;
  std::vector<int> axis_of_step;
  for (int k = 0; k < 2 * 5 * 100; ++k) {
    const double e = g.begin_step(in, axis);
    axis_of_step.push_back(axis);
    ASSERT_GE(axis, 0) << "step " << k;
    g.end_step(1e-3 * k, 1e-3 * k + e, 1e-6 * k);
    periods_seen = k;
  }
  (void)periods_seen;
  EXPECT_EQ(axis_of_step.front(), 0);
  EXPECT_EQ(axis_of_step[499], 0);
  EXPECT_EQ(axis_of_step[500], 2);
  EXPECT_TRUE(g.ready());
  EXPECT_EQ(g.status().state, SweepState::storing);
  EXPECT_EQ(g.status().completed, 1u);
  SweepCaptureView v = g.view();
  ASSERT_EQ(v.axes_done, 2);
  EXPECT_FALSE(v.aborted);
  // Axis 2's record starts after its two settle periods: step 500 + 200.
  const auto uc = v.channel(1, 1), u = v.channel(1, 2), e = v.channel(1, 0), y = v.channel(1, 3);
  ASSERT_EQ(uc.size(), 300u);
  EXPECT_FLOAT_EQ(uc[0], 0.7f);
  EXPECT_NEAR(u[5] - uc[5], e[5], 1e-6);
  EXPECT_FLOAT_EQ(y[0], 700e-6f);
  EXPECT_FLOAT_EQ(e[7], static_cast<float>(0.2 * g.design().table[7]));
  // A start while the record is held is refused (busy); release hands the buffer back.
  g.request_start();
  g.begin_step(in, axis);
  EXPECT_EQ(g.status().last_refusal, SweepRefusal::busy);
  g.release();
  g.begin_step(in, axis);
  EXPECT_EQ(g.status().state, SweepState::idle);
  // Orbit beyond the abort radius mid-sweep: aborted, counted, no excitation from then on.
  g.request_start();
  for (int k = 0; k < 150; ++k) {
    const double ex = g.begin_step(in, axis);
    g.end_step(0.0, ex, 0.0);
  }
  in.orbit_max_m = 1.1e-4;
  EXPECT_EQ(g.begin_step(in, axis), 0.0);
  EXPECT_EQ(axis, -1);
  EXPECT_EQ(g.status().aborts, 1u);
  EXPECT_EQ(g.status().last_abort, SweepAbort::orbit_limit);
  EXPECT_TRUE(g.view().aborted);
  EXPECT_EQ(g.view().axes_done, 0);
}

// The supervisor with the generator running over a whole sweep (four axes): no allocation.
TEST(SweepGenerator, ControlStepWithTheGeneratorRunningDoesNotAllocate) {
  amb::board::BoardConfig board = amb::board::load_board("bath-amb-rig");
  board.sweep.samples_per_period = 500;
  board.sweep.settle_periods = 1;
  board.sweep.recorded_periods = 2;
  Supervisor sup;
  sup.configure(board);
  amb::hal::AnalogInputs in{};
  amb::hal::DiscreteInputs din{};
  amb::hal::AnalogOutputs out{};
  amb::hal::DiscreteOutputs dout{};
  auto steps = [&](int n) {
    for (int i = 0; i < n; ++i) {
      in.t_ns += 100000;
      sup.step(in, true, din, out, dout);
    }
  };
  sup.post(Command::levitate);
  steps(static_cast<int>((board.lifecycle.liftoff_ramp_s + board.lifecycle.settle_s) * board.rate_hz) + 20);
  ASSERT_EQ(sup.status().phase, Phase::levitated);
  sup.request_sweep_start();
  const long before = amb::test::allocations();
  steps(4 * 3 * 500 + 10);
  const long after = amb::test::allocations();
  const Status st = sup.status();
  std::printf("[ RESULT ] supervisor step with the sweep generator: %ld allocations over %d steps; sweep %s, %u axes done\n",
              after - before, 4 * 3 * 500 + 10, to_string(st.sweep.state), st.sweep.axes_done);
  EXPECT_EQ(after - before, 0);
  EXPECT_EQ(st.sweep.started, 1u);
  EXPECT_EQ(st.sweep.completed, 1u);
  EXPECT_EQ(st.sweep.axes_done, 4);
  EXPECT_EQ(st.state, State::levitating);
  EXPECT_EQ(st.fault, FaultReason::none);
}

// A levitated supervisor on the Bath board with a short four-axis plan (500-sample periods,
// one settle and two recorded periods per axis) and fixed inputs: the position reading does not
// depend on the demand, so two of them given the same inputs run the same controller.
struct SweepRig {
  amb::board::BoardConfig board = amb::board::load_board("bath-amb-rig");
  Supervisor sup;
  amb::hal::AnalogInputs in{};
  amb::hal::DiscreteInputs din{};
  amb::hal::AnalogOutputs out{};
  amb::hal::DiscreteOutputs dout{};
  SweepRig() {
    board.sweep.samples_per_period = 500;
    board.sweep.settle_periods = 1;
    board.sweep.recorded_periods = 2;
    sup.configure(board);
    sup.post(Command::levitate);
    const int n = static_cast<int>((board.lifecycle.liftoff_ramp_s + board.lifecycle.settle_s) * board.rate_hz) + 20;
    for (int i = 0; i < n; ++i) {
      in.t_ns += 100000;
      sup.step(in, true, din, out, dout);
    }
  }
  // One period; once levitated the sensor readings move so that every axis's controller works.
  void step(long k) {
    in.t_ns += 100000;
    for (size_t i = 0; i < 4; ++i)
      in.displacement_m[i] = 2e-6 * std::sin(0.013 * static_cast<double>(k) * static_cast<double>(i + 1));
    sup.step(in, true, din, out, dout);
  }
};

bool same_sweep_status(const SweepStatus& a, const SweepStatus& b) {
  return a.state == b.state && a.axis == b.axis && a.axis_index == b.axis_index && a.axes_total == b.axes_total &&
         a.axes_done == b.axes_done && a.period == b.period && a.periods_per_axis == b.periods_per_axis &&
         a.started == b.started && a.completed == b.completed && a.aborts == b.aborts && a.refusals == b.refusals &&
         a.last_abort == b.last_abort && a.last_refusal == b.last_refusal;
}

// The generator publishes its status only when it changes (docs/sweep.md "Cost in the loop"):
// what other threads read through Supervisor::status() must still be the loop's own view after
// every step - through a refusal, a start, every settle and recorded period, each axis, a
// complete sweep, the hand-back of the record, an operator abort - and a refusal counted
// outside the loop must show at once.
TEST(SweepGenerator, PublishedStatusIsTheLoopsViewAfterEveryStep) {
  SweepRig r;
  ASSERT_EQ(r.sup.status().phase, Phase::levitated);
  ASSERT_TRUE(same_sweep_status(r.sup.status().sweep, r.sup.sweep().status()));
  long k = 0;
  int mismatches = 0;
  long first_mismatch = -1;
  uint32_t periods_seen = 0, last_period = 0;
  auto run = [&](int n) {
    for (int i = 0; i < n; ++i) {
      r.step(++k);
      const SweepStatus published = r.sup.status().sweep;
      if (!same_sweep_status(published, r.sup.sweep().status())) {
        if (mismatches++ == 0) first_mismatch = k;
      }
      if (published.period != last_period) ++periods_seen;
      last_period = published.period;
    }
  };
  // A refusal decided outside the loop (the supervisory link's "not armed").
  r.sup.sweep().count_refusal(SweepRefusal::not_armed);
  EXPECT_EQ(r.sup.status().sweep.refusals, 1u);
  EXPECT_EQ(r.sup.status().sweep.last_refusal, SweepRefusal::not_armed);
  run(5);
  // A whole sweep: 4 axes x 3 periods x 500 steps, then storing until the record is released.
  r.sup.request_sweep_start();
  run(4 * 3 * 500 + 10);
  EXPECT_EQ(r.sup.status().sweep.state, SweepState::storing);
  EXPECT_EQ(r.sup.status().sweep.completed, 1u);
  EXPECT_EQ(r.sup.status().sweep.axes_done, 4);
  EXPECT_GE(periods_seen, 4u * 3u - 1u);  // the published period moved with the loop's
  ASSERT_TRUE(r.sup.sweep().ready());
  r.sup.sweep().release();
  run(3);
  EXPECT_EQ(r.sup.status().sweep.state, SweepState::idle);
  // An operator abort in the second recorded period of the first axis.
  r.sup.request_sweep_start();
  run(1200);
  EXPECT_EQ(r.sup.status().sweep.state, SweepState::recording);
  r.sup.request_sweep_abort();
  run(3);
  EXPECT_EQ(r.sup.status().sweep.state, SweepState::storing);
  EXPECT_EQ(r.sup.status().sweep.aborts, 1u);
  EXPECT_EQ(r.sup.status().sweep.last_abort, SweepAbort::operator_abort);
  EXPECT_EQ(r.sup.status().sweep.started, 2u);
  std::printf("[ RESULT ] published sweep status vs the loop's: %d mismatches over %ld steps (first at %ld), %u period changes seen\n",
              mismatches, k, first_mismatch, periods_seen);
  EXPECT_EQ(mismatches, 0) << "first at step " << first_mismatch;
}

// The summing point: the swept axis's demand is the controller's demand (after its limit)
// plus the excitation, u = clamp(u_c + e); the other axes' demands are untouched. Checked
// against a second supervisor given the same inputs with no sweep, bit for bit, on all four
// axes, and the record's u_c, u, e channels against what went to the outputs.
TEST(SweepGenerator, ExcitationIsAddedAtTheSummingPointOfTheSweptAxisOnly) {
  SweepRig swept, plain;
  ASSERT_EQ(swept.sup.status().phase, Phase::levitated);
  const double lim = swept.board.controller.current_limit_a;
  // The start is taken at the next step (a settle step of axis 0), then the loop names the
  // axis of each step before it runs.
  swept.sup.request_sweep_start();
  long k = 1;
  swept.step(k);
  plain.step(k);
  ASSERT_EQ(swept.sup.sweep().status().axis, 0);
  int wrong_other = 0, wrong_swept = 0, wrong_record = 0, excited_steps = 0;
  std::array<int, 4> axis_steps{};
  axis_steps[0] = 1;
  std::vector<std::array<double, 3>> expected;  // per recorded step of the first axis: e, u_c, u
  const uint32_t n = swept.board.sweep.samples_per_period;
  for (int i = 1; i < 4 * 3 * static_cast<int>(n); ++i) {
    const SweepStatus before = swept.sup.sweep().status();
    swept.step(++k);
    plain.step(k);
    const int axis = (before.state == SweepState::settling || before.state == SweepState::recording) ? before.axis : -1;
    for (int a = 0; a < 4; ++a) {
      const double uc = plain.out.current_demand_a[static_cast<size_t>(a)];
      const double u = swept.out.current_demand_a[static_cast<size_t>(a)];
      if (a != axis) {
        wrong_other += u != uc;
        continue;
      }
      ++axis_steps[static_cast<size_t>(a)];
      const double e = u - uc;
      excited_steps += e != 0.0;
      // |e| within the amplitude times the crest-scaled table peak (table peak 1), and u clamped.
      wrong_swept += !(std::abs(e) <= swept.sup.sweep().amplitude_a() * 1.0000001) || std::abs(u) > lim;
      if (a == 0 && before.period >= swept.board.sweep.settle_periods) expected.push_back({e, uc, u});
    }
  }
  ASSERT_TRUE(swept.sup.sweep().ready());
  const SweepCaptureView v = swept.sup.sweep().view();
  ASSERT_EQ(v.axes_done, 4);
  ASSERT_EQ(v.axes[0], 0);
  const auto e0 = v.channel(0, 0), uc0 = v.channel(0, 1), u0 = v.channel(0, 2);
  ASSERT_EQ(expected.size(), e0.size());
  for (size_t j = 0; j < expected.size(); ++j)
    wrong_record += std::abs(uc0[j] - static_cast<float>(expected[j][1])) > 1e-6f * (1.0f + std::abs(uc0[j])) ||
                    std::abs(u0[j] - static_cast<float>(expected[j][2])) > 1e-6f * (1.0f + std::abs(u0[j])) ||
                    std::abs(e0[j] - static_cast<float>(expected[j][0])) > 1e-5f;
  std::printf("[ RESULT ] summing point: %d excited steps, steps per axis %d %d %d %d; demand differences off the swept axis %d, "
              "swept axis out of bounds %d, record mismatches %d\n",
              excited_steps, axis_steps[0], axis_steps[1], axis_steps[2], axis_steps[3], wrong_other, wrong_swept, wrong_record);
  EXPECT_EQ(wrong_other, 0);
  EXPECT_EQ(wrong_swept, 0);
  EXPECT_EQ(wrong_record, 0);
  for (int a = 0; a < 4; ++a) EXPECT_EQ(axis_steps[static_cast<size_t>(a)], 3 * static_cast<int>(n)) << "axis " << a;
  EXPECT_GT(excited_steps, 4 * 3 * static_cast<int>(n) * 9 / 10);
  EXPECT_EQ(swept.sup.status().fault, FaultReason::none);
}

SweepEvent small_event() {
  SweepEvent e;
  e.meta.board_name = "b";
  e.meta.rig_name = "r";
  e.meta.rate_hz = 1000.0;
  e.samples_per_period = 16;
  e.settle_periods = 1;
  e.recorded_periods = 2;
  e.amplitude_a = 0.25;
  e.crest_factor = 1.5;
  e.bias_current_a = 2.5;
  e.bins = {1, 3, 5};
  e.aborted = true;
  e.abort_reason = SweepAbort::orbit_limit;
  for (uint8_t a : {uint8_t{3}, uint8_t{1}}) {
    SweepAxisData x;
    x.axis = a;
    for (int k = 0; k < 32; ++k) {
      x.excitation_a.push_back(0.01f * k);
      x.controller_output_a.push_back(-0.02f * k + a);
      x.summing_point_a.push_back(0.5f * k);
      x.sensor_m.push_back(1e-6f * k);
    }
    e.axes.push_back(x);
  }
  return e;
}

TEST(SweepEventCodec, RoundTripsAndRefusesCorruptionNamingIt) {
  const SweepEvent e = small_event();
  const std::vector<uint8_t> bytes = encode_sweep_event(e);
  EXPECT_EQ(bytes.size(), sweep_event_file_bytes(3, 2, 32));
  SweepEvent back;
  std::string err;
  ASSERT_TRUE(decode_sweep_event(bytes, back, err)) << err;
  EXPECT_EQ(back.format_version, 4);
  EXPECT_EQ(back.bins, e.bins);
  ASSERT_EQ(back.axes.size(), 2u);
  EXPECT_EQ(back.axes[0].axis, 3);
  EXPECT_EQ(back.axes[1].controller_output_a, e.axes[1].controller_output_a);
  EXPECT_EQ(back.axes[0].sensor_m, e.axes[0].sensor_m);
  EXPECT_TRUE(back.aborted);
  EXPECT_EQ(back.abort_reason, SweepAbort::orbit_limit);
  EXPECT_EQ(encode_sweep_event(back), bytes);
  // The drop decoder refuses it, naming the kind; the sweep decoder refuses a drop event.
  EventRecord r;
  EXPECT_FALSE(decode_event(bytes, r, err));
  EXPECT_NE(err.find("not a drop event"), std::string::npos) << err;
  EventRecord drop;
  drop.meta.rate_hz = 1000.0;
  drop.samples.resize(2);
  EXPECT_FALSE(decode_sweep_event(encode_event(drop), back, err));
  EXPECT_NE(err.find("not a sweep event"), std::string::npos) << err;
  // A flipped byte: checksum; cut short: truncated.
  std::vector<uint8_t> bad = bytes;
  bad[700] ^= 0x40;
  EXPECT_FALSE(decode_sweep_event(bad, back, err));
  EXPECT_NE(err.find("bad checksum"), std::string::npos) << err;
  bad.assign(bytes.begin(), bytes.begin() + 900);
  EXPECT_FALSE(decode_sweep_event(bad, back, err));
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;
  // A consistent file (CRC recomputed) whose content is wrong: named.
  auto recrc = [](std::vector<uint8_t> b) {
    const uint32_t c = amb::fw::crc32(std::span<const uint8_t>(b.data(), b.size() - 4));
    for (int i = 0; i < 4; ++i) b[b.size() - 4 + static_cast<size_t>(i)] = static_cast<uint8_t>(c >> (8 * i));
    return b;
  };
  SweepEvent w = e;
  w.bins = {3, 1, 5};
  EXPECT_FALSE(decode_sweep_event(encode_sweep_event(w), back, err));
  EXPECT_NE(err.find("line 1 at bin 1"), std::string::npos) << err;
  w = e;
  w.axes[1].axis = 3;
  EXPECT_FALSE(decode_sweep_event(encode_sweep_event(w), back, err));
  EXPECT_NE(err.find("axis block for axis 3"), std::string::npos) << err;
  bad = bytes;
  bad[6] = 7;  // record kind
  EXPECT_FALSE(decode_sweep_event(recrc(bad), back, err));
  EXPECT_NE(err.find("unknown record kind 7"), std::string::npos) << err;
  // A drop event as version 4, kind drop, reads as the version-3 layout.
  std::vector<uint8_t> v4 = encode_event(drop);
  v4[4] = 4;
  ASSERT_TRUE(decode_event(recrc(v4), r, err)) << err;
  EXPECT_EQ(r.format_version, 4);
  EXPECT_EQ(r.samples.size(), 2u);
}

TEST(SweepStatusFrame, RoundTripsAndRefusesForeignFrames) {
  amb::fieldbus::SweepStatusFrame s;
  s.state = 2;
  s.axis = 3;
  s.axes_done = 2;
  s.axes_total = 4;
  s.period = 513;
  s.aborts = 7;
  s.refusals = 9;
  s.last_abort = static_cast<uint8_t>(SweepAbort::orbit_limit);
  s.last_refusal = static_cast<uint8_t>(SweepRefusal::not_armed);
  const amb::hal::CanFrame f = amb::fieldbus::encode_sweep_status(1, s);
  EXPECT_EQ(f.id, 0x581u);
  amb::fieldbus::SweepStatusFrame b;
  ASSERT_TRUE(amb::fieldbus::decode_sweep_status(f, 1, b));
  EXPECT_EQ(b.axis, 3);
  EXPECT_EQ(b.period, 513);
  EXPECT_EQ(b.last_refusal, s.last_refusal);
  EXPECT_EQ(b.axes_done, 2);
  EXPECT_FALSE(amb::fieldbus::decode_sweep_status(f, 2, b));
  amb::hal::CanFrame g = f;
  g.data[0] = 0x0F;  // state 15
  EXPECT_FALSE(amb::fieldbus::decode_sweep_status(g, 1, b));
  s.axis = -1;
  ASSERT_TRUE(amb::fieldbus::decode_sweep_status(amb::fieldbus::encode_sweep_status(1, s), 1, b));
  EXPECT_EQ(b.axis, -1);
}

}  // namespace

namespace {
// The board budget lists the sweep's record buffer as the generator allocates it.
TEST(SweepBudget, RecordBufferEntryIsWhatTheGeneratorHolds) {
  for (const char* name : {"bath-amb-rig", "unicamp-amb-rig"}) {
    const amb::board::BoardConfig b = amb::board::load_board(name);
    Supervisor sup;
    sup.configure(b);
    uint64_t listed = 0;
    for (const BufferBudget& e : buffer_budget(b))
      if (e.name == "sweep record buffer") listed = e.bytes;
    std::printf("[ RESULT ] %s: sweep record buffer %llu B listed, %zu B held\n", name,
                static_cast<unsigned long long>(listed), sup.sweep().buffer_bytes());
    EXPECT_EQ(listed, sup.sweep().buffer_bytes()) << name;
    EXPECT_GT(listed, 0u);
  }
}
}  // namespace
