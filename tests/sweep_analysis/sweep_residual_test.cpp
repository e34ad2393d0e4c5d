// The residual loop on the board's own sweep (sweep_residual.hpp) with effects nobody declared,
// put into the simulated plant only (sweep_sil.hpp; the analysis is not told): an extra
// amplifier lag, and separately a pedestal resonance under AMB A. The sweep's residual names
// it, the fitted values are near the injected ones, the zone the model with the found element
// predicts is the measured one, and the error falls. Clean sweeps over seeds and amplitudes
// give the false-alarm rate (a handful here; more in the long-labelled case).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "host-tools/core/sweep/sweep_analysis.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/sweep_analysis/sweep_sil.hpp"

using namespace amb;
namespace fx = model::effects;

namespace {

board::BoardConfig board_of(const char* name) {
  return board::load_board(std::string(test::source_dir()) + "/boards/" + name + ".toml");
}

host::sweep::SweepAnalysis run(const board::BoardConfig& b, const test::SilSweepOptions& o, const char* what) {
  const host::sweep::SweepRecord r = test::run_sil_sweep(b, o);
  const host::sweep::SweepAnalysis a = host::sweep::analyse_sweep(r, b);
  const auto& res = a.residual;
  std::printf("[ RESULT ] %s on %s (seed %llu, amplitude %.3g of bias): verdict %s; S error %.2f -> %.2f dB rms, G error %.2f -> "
              "%.2f dB rms, misfit %.4g -> %.4g\n",
              what, b.name.c_str(), static_cast<unsigned long long>(o.seed), o.amplitude_fraction, res.verdict.c_str(),
              res.before.s_db_rms, res.after.s_db_rms, res.before.g_db_rms, res.after.g_db_rms, res.before.misfit, res.after.misfit);
  for (const auto& c : res.ranking) std::printf("           %-20s dBIC %9.1f %s\n", c.name.c_str(), c.delta_bic, c.reason.c_str());
  for (const auto& e : res.effects_added)
    for (const auto& [n, v] : e.parameters) std::printf("           fitted %s.%s = %.5g\n", e.name.c_str(), n.c_str(), v);
  for (size_t i = 0; i < a.zones.size(); ++i)
    std::printf("           axis %s: measured %s; board model %s (%.3g); with the elements %s (%.3g)\n", a.zones[i].axis_name.c_str(),
                a.zones[i].measured.statement.c_str(), res.before.model_zone[i].c_str(), res.before.model_peak[i],
                res.after.model_zone[i].c_str(), res.after.model_peak[i]);
  return a;
}

double param(const host::sweep::SweepAnalysis& a, const std::string& element, const std::string& name) {
  for (const auto& e : a.residual.effects_added)
    if (e.name == element)
      for (const auto& [n, v] : e.parameters)
        if (n == name) return v;
  return std::nan("");
}

// Zone of the measured peak equals the zone the found model predicts, on every axis; the board
// model's zone differs on at least one (the effect changes the rating).
void expect_zone_follows(const host::sweep::SweepAnalysis& a) {
  bool changed = false;
  for (size_t i = 0; i < a.zones.size(); ++i) {
    EXPECT_EQ(a.zones[i].measured.zone, a.residual.after.model_zone[i]) << a.zones[i].axis_name;
    EXPECT_NEAR(a.residual.after.peak_ratio[i], 1.0, 0.05) << a.zones[i].axis_name;
    changed = changed || a.residual.before.model_zone[i] != a.zones[i].measured.zone;
  }
  EXPECT_TRUE(changed) << "the effect did not change any axis' zone";
}

// The generator's extra lag (model/effects/effect_plant.cpp) is updated once per plant step,
// and the sim backend steps the plant once per loop period T: a discrete first-order lag
// b = exp(-T / tau), whose continuous equivalent at low frequency is T b / (1 - b) (58 us for
// tau = 100 us at 10 kHz). That equivalent is what the loop carries and what the fit must find.
TEST(SweepResidual, ExtraAmplifierLagIsNamed) {
  const board::BoardConfig b = board_of("bath-amb-rig");
  test::SilSweepOptions o;
  const double tau = 1e-4, t = 1.0 / b.rate_hz, bb = std::exp(-t / tau), equivalent = t * bb / (1.0 - bb);
  o.effects.amplifier_lag = fx::AmplifierLag{tau};
  const auto a = run(b, o, "amplifier lag 100 us (discrete: 58 us equivalent)");
  ASSERT_FALSE(a.residual.effects_added.empty());
  EXPECT_EQ(a.residual.effects_added.front().name, "amplifier_lag");
  const double fitted = param(a, "amplifier_lag", "time_constant_s");
  std::printf("[ RESULT ] fitted extra lag %.1f us; the generator's continuous equivalent %.1f us (%+.1f %%)\n", fitted * 1e6,
              equivalent * 1e6, 100.0 * (fitted / equivalent - 1.0));
  EXPECT_NEAR(fitted, equivalent, 0.1 * equivalent);
  EXPECT_LT(a.residual.after.s_db_rms, 0.5 * a.residual.before.s_db_rms);
  expect_zone_follows(a);
}

void pedestal_case(const char* rig) {
  const board::BoardConfig b = board_of(rig);
  test::SilSweepOptions o;
  o.effects.pedestal = fx::PedestalResonance{0, 10.0, 60.0, 0.03};
  const auto a = run(b, o, "pedestal 10 kg, 60 Hz, 3 % under AMB A");
  ASSERT_FALSE(a.residual.effects_added.empty());
  EXPECT_EQ(a.residual.effects_added.front().name, "pedestal_resonance");
  EXPECT_NEAR(param(a, "pedestal_resonance", "frequency_hz"), 60.0, 0.1 * 60.0);
  EXPECT_NEAR(param(a, "pedestal_resonance", "mass_kg"), 10.0, 0.2 * 10.0);
  ASSERT_TRUE(a.residual.found.pedestal.has_value());
  EXPECT_EQ(a.residual.found.pedestal->plane, 0);
  EXPECT_LT(a.residual.after.s_db_rms, 0.5 * a.residual.before.s_db_rms);
  expect_zone_follows(a);
}

TEST(SweepResidual, PedestalResonanceIsNamed) { pedestal_case("bath-amb-rig"); }
TEST(SweepResidual, PedestalResonanceIsNamedOnUnicamp) { pedestal_case("unicamp-amb-rig"); }

// False alarms: clean sweeps (no effect) with different noise seeds and amplitudes.
int false_alarms(const char* rig, int seeds, const std::vector<double>& amplitudes, int& runs) {
  const board::BoardConfig b = board_of(rig);
  int alarms = 0;
  for (int s = 1; s <= seeds; ++s)
    for (double amp : amplitudes) {
      test::SilSweepOptions o;
      o.seed = static_cast<std::uint64_t>(100 + s);
      o.amplitude_fraction = amp;
      const auto a = run(b, o, "clean");
      alarms += a.residual.effects_added.empty() ? 0 : 1;
      ++runs;
    }
  return alarms;
}

TEST(SweepResidual, CleanSweepsRaiseNoElement) {
  int runs = 0;
  const int alarms = false_alarms("bath-amb-rig", 2, {0.03, 0.05}, runs) + false_alarms("unicamp-amb-rig", 1, {0.05}, runs);
  std::printf("[ RESULT ] clean sweeps: %d false alarms in %d runs\n", alarms, runs);
  EXPECT_EQ(alarms, 0);
}

TEST(SweepResidualLong, CleanSweepFalseAlarmRate) {
  int runs = 0;
  const int alarms = false_alarms("bath-amb-rig", 8, {0.02, 0.035, 0.05}, runs) + false_alarms("unicamp-amb-rig", 4, {0.03, 0.05}, runs);
  // 95 % upper bound of the rate (Clopper-Pearson; zero alarms: 1 - 0.05^(1/n)).
  const double upper = alarms == 0 ? 1.0 - std::pow(0.05, 1.0 / runs) : std::nan("");
  std::printf("[ RESULT ] clean sweeps (long): %d false alarms in %d runs; 95 %% upper bound of the rate %.3f\n", alarms, runs, upper);
  EXPECT_LE(alarms, 1);
}

}  // namespace
