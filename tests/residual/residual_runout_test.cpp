// Sensor runout against unbalance at one speed, on generated records (the generator writes
// files; the code under test gets only the sidecar and is not told what was injected).
// Unbalance is a real force: the rotor moves and the AMB law (F = ks x + ki i with the
// rotor's dynamics) holds for the measured displacement. Runout is a measurement artefact:
// the PID turns it into currents, but the displacement-current pair then violates that law
// by the runout. The steady fit solves a two-plane unbalance and, for the candidate, the
// runout phasors together from the 8 channels' line phasors; the BIC says which.
// Limit of the levitated part (docs/residual.md): the controller acts on the measured
// displacement, so the current is the known controller's response to (x_true + r), and a
// purely 1x forward runout at one speed is exactly what a two-plane unbalance can produce.
// What tells them apart at one speed is the drop: after the cut no controller acts, the rotor
// is held on the aux-bearing circles, and runout stays in the readings as a spin-locked
// departure from those circles, while unbalance only bends the shaft between the contacts
// (a known, small signature). The drop-event tests below check that on generated drops.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/residual/residual_loop.hpp"
#include "host-tools/core/residual/steady_data.hpp"
#include "host-tools/core/scenario/steady_record.hpp"

using namespace amb;
namespace fx = amb::model::effects;
namespace hr = amb::host::residual;

namespace {

struct Result {
  hr::ResidualOutcome outcome;
  double plane_a_1x_m = 0.0;  ///< measured 1x amplitude at sensor A1, m (what both records share)
};

Result run(const std::string& stem, const fx::EffectSet& e, double unbalance_scale) {
  const auto dir = std::filesystem::temp_directory_path() / ("amb_residual_runout_" + std::to_string(::getpid()));
  host::SteadyRecordOptions so;
  so.unbalance_scale = unbalance_scale;
  const std::string path = host::generate_steady_record(dir.string(), stem, e, so);
  // The code under test: the file in, the outcome out.
  const auto rec = host::load_event(path);
  const auto b = board::load_board(rec.board);
  const auto d = hr::extract_steady(rec, b);
  Result r{hr::run_residual_loop(d, b), std::abs(d.order[0][0])};
  std::printf("[ RESULT ] %-10s 1x at A1 %.2f um -> verdict %s, rms %.4f -> %.4f\n", stem.c_str(), r.plane_a_1x_m * 1e6,
              r.outcome.verdict.c_str(), r.outcome.before.error.rms, r.outcome.after.error.rms);
  for (const auto& c : r.outcome.ranking) std::printf("           rank %-20s dBIC %10.1f\n", c.name.c_str(), c.delta_bic);
  std::filesystem::remove_all(dir);
  return r;
}

}  // namespace

TEST(ResidualRunout, UnbalanceIsNotTakenForRunout) {
  // Unbalance 8 x the board's: a real 1x force, about 20 um 1x readings at plane A. It is
  // the base model's own unknown (two-plane unbalance): no runout may be named for it.
  const Result u = run("unbalance", {}, 8.0);
  EXPECT_GT(u.plane_a_1x_m, 10e-6);
  EXPECT_EQ(u.outcome.verdict.find("sensor_runout"), std::string::npos) << u.outcome.verdict;
  for (const auto& c : u.outcome.ranking) {
    if (c.name == "sensor_runout") {
      EXPECT_LT(c.delta_bic, 0.0) << c.evidence;
    }
  }
}

TEST(ResidualRunout, RunoutWithA2xComponentIsNamedAndSeparatedFromUnbalance) {
  // 1x runout at plane A (6.7 um) and 2x at plane B (4 um), board unbalance. The 1x part
  // alone is not separable from a two-plane unbalance at one speed (see docs/residual.md);
  // with the element in the model the 1x phasors are split between unbalance and runout by
  // the displacement-current relation, and the A 1x amplitude must come out right.
  fx::EffectSet e;
  fx::SensorRunout ro;
  ro.r_m[0][0] = {6e-6, 3e-6};
  ro.r_m[1][1] = {0.0, 4e-6};
  e.runout = ro;
  const Result r = run("runout", e, 8.0);
  ASSERT_FALSE(r.outcome.effects_added.empty());
  EXPECT_EQ(r.outcome.effects_added.front().name, "sensor_runout");
  double a1 = -1.0, b2 = -1.0;
  for (const auto& [k, v] : r.outcome.effects_added.front().parameters) {
    if (k == "amplitude_a_order1_m") a1 = v;
    if (k == "amplitude_b_order2_m") b2 = v;
  }
  EXPECT_NEAR(a1, std::abs(ro.r_m[0][0]), 0.2 * std::abs(ro.r_m[0][0]));
  EXPECT_NEAR(b2, std::abs(ro.r_m[1][1]), 0.2 * std::abs(ro.r_m[1][1]));
  // Not asserted: the B-plane 1x runout (true 0) comes out at 4.1 um with this unbalance,
  // the 1x split between unbalance and runout is not unique at one speed (docs/residual.md).
}

namespace {

// A generated drop event at 45 Hz with a spin-speed record (tachometer): the code under test
// gets only the sidecar.
hr::DropResidualOutcome run_drop(const std::string& stem, const fx::EffectSet& e, double unbalance_scale) {
  const auto dir = std::filesystem::temp_directory_path() / ("amb_residual_runout_drop_" + std::to_string(::getpid()));
  host::SteadyRecordOptions so;
  so.unbalance_scale = unbalance_scale;
  so.drop_s = 0.4;
  so.tachometer = true;
  const std::string path = host::generate_steady_record(dir.string(), stem, e, so);
  const auto rec = host::load_event(path);
  const auto b = board::load_board(rec.board);
  auto o = hr::run_drop_residual(rec, b);
  std::printf("[ RESULT ] drop %-14s -> verdict %s (levitated %s), runout applied from '%s'\n", stem.c_str(), o.verdict.c_str(),
              o.levitated.verdict.c_str(), o.runout_source.c_str());
  for (size_t p = 0; p < 2; ++p)
    for (size_t h = 0; h < 2; ++h)
      std::printf("           contact runout %c %zux: %.2f um (sigma %.2f um)\n", p == 0 ? 'A' : 'B', h + 1,
                  std::abs(o.drop_runout.runout.r_m[p][h]) * 1e6, o.drop_runout.sigma_m[p][h] * 1e6);
  std::printf("           1x floor A %.2f um, B %.2f um\n", o.runout_floor_m[0] * 1e6, o.runout_floor_m[1] * 1e6);
  for (const auto& c : o.drop_ranking) std::printf("           drop rank %-22s dBIC %8.1f  %s\n", c.name.c_str(), c.delta_bic, c.evidence.c_str());
  for (const auto& n : o.drop_notes) std::printf("           drop note: %s\n", n.c_str());
  std::filesystem::remove_all(dir);
  return o;
}

double parameter(const hr::EffectAdded& e, const std::string& k) {
  for (const auto& [n, v] : e.parameters)
    if (n == k) return v;
  return -1.0;
}

}  // namespace

TEST(ResidualRunout, OneSpeedDropTellsA1xRunoutFromUnbalance) {
  // A 1x runout at plane A only (6.7 um) with the board's unbalance: the levitated part alone
  // cannot separate it (see above); the drop part must name it, at plane A, and not invent
  // one at plane B.
  fx::EffectSet e;
  fx::SensorRunout ro;
  ro.r_m[0][0] = {6e-6, 3e-6};
  e.runout = ro;
  const auto o = run_drop("runout_1x", e, 1.0);
  ASSERT_TRUE(o.drop_runout.testable) << o.drop_runout.why_not;
  const hr::EffectAdded* r = nullptr;
  for (const auto& a : o.effects_added)
    if (a.name == "sensor_runout") r = &a;
  ASSERT_NE(r, nullptr) << "runout not named; verdict " << o.verdict;
  EXPECT_NEAR(parameter(*r, "amplitude_a_order1_m"), std::abs(ro.r_m[0][0]), 0.25 * std::abs(ro.r_m[0][0]));
  EXPECT_LT(parameter(*r, "amplitude_b_order1_m"), 2e-6);
  for (const auto& a : o.effects_added) EXPECT_EQ(a.name, "sensor_runout") << "a filler was named";
}

TEST(ResidualRunout, OneSpeedDropDoesNotTakeUnbalanceForRunout) {
  // Unbalance 8 x the board's (about 20 um 1x readings at plane A while levitated), no runout,
  // the same speed: no runout may be named in either part.
  const auto o = run_drop("unbalance", {}, 8.0);
  ASSERT_TRUE(o.drop_runout.testable) << o.drop_runout.why_not;
  EXPECT_EQ(o.verdict.find("sensor_runout"), std::string::npos) << o.verdict;
}
