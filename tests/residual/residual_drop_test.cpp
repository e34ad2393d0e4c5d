// The residual loop on generated DROP events: the firmware levitates the board's plant with
// one model element switched on (undeclared: declared_faults = []), holds a steady speed,
// then all amplifier channels are cut and the rotor falls onto its auxiliary bearings. The
// record keeps the last 2.3 s of levitation (a capture's pre-trigger history) and 0.4 s of
// the drop. The code under test gets only the sidecar path: it must see that this is a drop
// event, name the element, make the error fall, and add nothing on a clean event.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <unistd.h>

#include "model/rotor/modal_reduction.hpp"
#include "firmware/board/board.hpp"
#include "tests/support/test_paths.hpp"
#include "host-tools/core/residual/drop_residual.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/scenario/steady_record.hpp"

using namespace amb;
namespace fx = amb::model::effects;
namespace hr = amb::host::residual;

namespace {

hr::DropResidualOutcome analyse(const std::string& sidecar) {
  const auto rec = host::load_event(sidecar);
  const auto b = board::load_board(rec.board);
  std::string why;
  EXPECT_TRUE(hr::is_drop_event(rec, b, &why)) << why;
  // One rig model per run (issue 37): every fit, refit and loop model of the residual run
  // shares it, so the FE rotor is assembled and its eigenproblem solved exactly once.
  const auto before = amb::model::rotor::build_counts();
  auto out = hr::run_drop_residual(rec, b);
  const auto after = amb::model::rotor::build_counts();
  EXPECT_EQ(after.fe_builds - before.fe_builds, 1) << "FE rotor builds in one drop residual run";
  EXPECT_EQ(after.eigen_solves - before.eigen_solves, 1) << "modal eigen solves in one drop residual run";
  return out;
}

std::string temp_dir() {
  static const std::string dir = [] {
    const auto p = std::filesystem::temp_directory_path() / ("amb_residual_drop_" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    return p.string();
  }();
  return dir;
}

void report(const std::string& injected, const hr::DropResidualOutcome& o) {
  std::printf("[ RESULT ] drop, injected %-20s -> verdict %-24s rms %.4f -> %.4f, spectral %.2f -> %.2f dB, pearson %.3f -> "
              "%.3f, statics %.4f -> %.4f\n",
              injected.c_str(), o.verdict.c_str(), o.before.rms, o.after.rms, o.before.spectral, o.after.spectral,
              o.before.pearson, o.after.pearson, o.before.statics, o.after.statics);
  std::printf("           drop part: rms %.4f -> %.4f, spectral %.2f -> %.2f dB, contact misfit %.4f -> %.4f, mu %.3f -> %.3f\n",
              o.drop_before.error.rms, o.drop_after.error.rms, o.drop_before.error.spectral, o.drop_after.error.spectral,
              o.drop_before.error.statics, o.drop_after.error.statics, o.drop_before.friction_coefficient,
              o.drop_after.friction_coefficient);
  if (!o.levitated_analysed) std::printf("           %s\n", o.levitated_note.c_str());
  else
    std::printf("           levitated part: verdict %s, rms %.4f -> %.4f, spectral %.2f -> %.2f dB, pearson %.3f -> %.3f\n",
                o.levitated.verdict.c_str(), o.levitated.before.error.rms, o.levitated.after.error.rms,
                o.levitated.before.error.spectral, o.levitated.after.error.spectral, o.levitated.before.error.pearson,
                o.levitated.after.error.pearson);
  for (const auto& a : o.effects_added) {
    std::printf("           added %s:", a.name.c_str());
    for (const auto& [k, v] : a.parameters) std::printf(" %s=%.4g", k.c_str(), v);
    std::printf("\n");
  }
  for (const auto& c : o.drop_ranking) std::printf("           drop rank %-20s dBIC %8.1f  %s\n", c.name.c_str(), c.delta_bic, c.evidence.c_str());
  for (const auto& n : o.drop_notes) std::printf("           drop note: %s\n", n.c_str());
  for (const auto& u : o.unexplained)
    std::printf("           unexplained (%s) %s %.1f Hz plane %d level %.1f dB snr %.1f\n", u.part.c_str(), u.kind.c_str(), u.f_hz, u.plane,
                u.level_db, u.snr);
}

hr::DropResidualOutcome run_case(const std::string& stem, const fx::EffectSet& e, bool tachometer = false) {
  host::SteadyRecordOptions g;
  g.drop_s = 0.4;
  g.seed = 7;
  g.tachometer = tachometer;
  const std::string path = host::generate_steady_record(temp_dir(), "drop_" + stem, e, g);
  auto o = analyse(path);
  report(stem, o);
  std::filesystem::remove(path);
  std::filesystem::remove(std::filesystem::path(path).replace_extension(".csv"));
  return o;
}

bool falls(const hr::ErrorFigures& b, const hr::ErrorFigures& a) {
  return a.spectral <= 0.9 * b.spectral || a.rms <= 0.9 * b.rms || a.statics <= 0.9 * b.statics;
}

// Named first; the error of the part it acts in falls (one figure by >= 10 %, none rises by
// more than 10 %); none of the whole event's figures rises by more than 10 %.
void expect_named(const hr::DropResidualOutcome& o, const std::string& name, bool acts_while_levitated = true) {
  ASSERT_FALSE(o.effects_added.empty()) << "nothing added; expected " << name;
  EXPECT_EQ(o.effects_added.front().name, name);
  ASSERT_TRUE(o.levitated_analysed) << o.levitated_note;
  const hr::ErrorFigures& b = acts_while_levitated ? o.levitated.before.error : o.drop_before.error;
  const hr::ErrorFigures& a = acts_while_levitated ? o.levitated.after.error : o.drop_after.error;
  EXPECT_TRUE(falls(b, a)) << "the error of the part the element acts in does not fall";
  EXPECT_LE(a.spectral, 1.1 * b.spectral);
  EXPECT_LE(a.rms, 1.1 * b.rms);
  EXPECT_LE(o.after.rms, 1.1 * o.before.rms);
  EXPECT_LE(o.after.spectral, 1.1 * o.before.spectral);
  EXPECT_LE(o.after.statics, 1.1 * o.before.statics);
}

// Not kept because a reported error rises with it (the rule: an element is kept only when no
// reported error rises): nothing else may be named instead, and the part it acts in must
// at least show the model update's gain.
void expect_no_filler(const hr::DropResidualOutcome& o, const std::string& name) {
  for (const auto& a : o.effects_added) EXPECT_EQ(a.name, name) << "a filler was named instead";
  ASSERT_TRUE(o.levitated_analysed) << o.levitated_note;
  EXPECT_LT(o.levitated.updated.error.spectral, o.levitated.before.error.spectral);
}

}  // namespace

TEST(ResidualDrop, CleanDropAddsNothing) {
  const auto o = run_case("clean", {});
  EXPECT_TRUE(o.levitated_analysed) << o.levitated_note;
  EXPECT_EQ(o.verdict, "none");
}

TEST(ResidualDrop, AuxBearingOffsetIsNamedAndKeptOnItsEvidence) {
  // A rig with a spin record through the drop (tachometer). The offset must be found from
  // the contact circles and kept by the engine's criterion on the contact geometry (the
  // post-impact trajectory is chaotic: reported, never a veto), and the decision's features
  // must fall. Accuracy: this plant's rotor is flexible, and its contact points are read at
  // the aux planes through its bending (ContactView; the straight line through the sensor
  // planes put the vertical centres 6-10 um low), so every component within 3 um.
  fx::EffectSet e;
  e.aux_offset = fx::AuxBearingOffset{{60e-6, -50e-6}, {-40e-6, 30e-6}};  // x_m, y_m per aux bearing
  const auto o = run_case("aux_bearing_offset", e, true);
  ASSERT_EQ(o.verdict, "aux_bearing_offset");
  ASSERT_EQ(o.effects_added.front().parameters.size(), 5u);
  const auto& p = o.effects_added.front().parameters;
  EXPECT_NEAR(p[0].second, 60e-6, 3e-6);   // x0
  EXPECT_NEAR(p[1].second, -40e-6, 3e-6);  // y0
  EXPECT_NEAR(p[2].second, -50e-6, 3e-6);  // x1
  EXPECT_NEAR(p[3].second, 30e-6, 3e-6);   // y1
  const hr::CandidateScore* c = nullptr;
  for (const auto& r : o.drop_ranking)
    if (r.name == "aux_bearing_offset") c = &r;
  ASSERT_NE(c, nullptr);
  ASSERT_TRUE(c->decided && c->kept) << c->reason;
  EXPECT_GT(c->delta_bic, c->threshold);
  ASSERT_FALSE(c->decision_features.empty());
  for (const auto& f : c->decision_features) EXPECT_LE(f.after, f.before * 1.01 + 1e-12) << f.name;
  EXPECT_LT(o.drop_after.error.statics, 0.9 * o.drop_before.error.statics);
  EXPECT_FALSE(c->information_features.empty()) << "the chaotic remainder must be reported";
}

TEST(ResidualDrop, SensorRunoutIsNamed) {
  fx::EffectSet e;
  fx::SensorRunout r;
  r.r_m[0][0] = {6e-6, 3e-6};
  r.r_m[1][1] = {0.0, 4e-6};
  e.runout = r;
  expect_named(run_case("sensor_runout", e), "sensor_runout");
}

TEST(ResidualDrop, SensorGainIsNamed) {
  // Probe A1 reads 8 % high: the contact circle at the aux planes is read as an ellipse. The
  // element must be named and its gain ratio A1/A2 found within 2 % (no rotor angle needed).
  fx::EffectSet e;
  fx::SensorGain g;
  g.gain[0] = 1.08;
  e.sensor_gain = g;
  const auto o = run_case("sensor_gain", e);
  bool named = false;
  for (const auto& a : o.effects_added)
    if (a.name == "sensor_gain") {
      named = true;
      EXPECT_NEAR(a.parameters.at(0).second, 1.08, 0.02) << a.parameters.at(0).first;
      EXPECT_NEAR(a.parameters.at(1).second, 1.0, 0.02) << a.parameters.at(1).first;
    }
  EXPECT_TRUE(named) << o.verdict;
}

TEST(ResidualDrop, OffsetAndRunoutTogether) {
  // Two effects at once, with a spin record: both named and kept together.
  fx::EffectSet e;
  e.aux_offset = fx::AuxBearingOffset{{50e-6, -40e-6}, {-60e-6, 30e-6}};  // x_m, y_m per aux bearing
  fx::SensorRunout r;
  // 7 um: the drop part names a 1x runout from about 5 um (population, docs/residual.md); a
  // static runout is read about 3.3x at standstill with the Bath rig's slow integral action, so
  // above about 10 um the board's lift-off settle tolerance is not met.
  r.r_m[0][0] = {6.5e-6, 2.5e-6};
  e.runout = r;
  const auto o = run_case("offset_runout", e, true);
  std::set<std::string> named;
  for (const auto& x : o.effects_added) {
    named.insert(x.name);
    if (x.name != "aux_bearing_offset") continue;
    // The offsets within 5 um with the runout taken out beside them.
    const double truth[4] = {50e-6, -60e-6, -40e-6, 30e-6};  // x0, y0, x1, y1
    for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(x.parameters.at(k).second, truth[k], 5e-6) << x.parameters.at(k).first;
  }
  EXPECT_EQ(named.count("aux_bearing_offset"), 1u) << o.verdict;
  EXPECT_EQ(named.count("sensor_runout"), 1u) << o.verdict;
}

TEST(ResidualDrop, PedestalResonanceIsNamed) {
  // As ResidualSteady.PedestalResonanceIsNamed: the pedestal is the best candidate but its
  // rms rises, so it is not kept (known limit); no filler may be named instead.
  // 10 kg: see there.
  fx::EffectSet e;
  e.pedestal = fx::PedestalResonance{0, 10.0, 37.0, 0.02};
  expect_no_filler(run_case("pedestal_resonance", e), "pedestal_resonance");
}

TEST(ResidualDrop, AmplifierLagIsNamed) {
  fx::EffectSet e;
  e.amplifier_lag = fx::AmplifierLag{0.1e-3};
  expect_named(run_case("amplifier_lag", e), "amplifier_lag");
}

TEST(ResidualDrop, RotorModeIsNamed) {
  fx::EffectSet e;
  e.rotor_mode = fx::RotorMode{1.25};
  expect_named(run_case("rotor_mode", e), "rotor_mode");
}

TEST(ResidualDrop, MagneticSaturationIsNamed) {
  fx::EffectSet e;
  e.saturation = fx::MagneticSaturation{10.0};
  // As ResidualSteady.MagneticSaturationIsNamed: the model update (force scale) takes part of
  // it and saturation is not kept (its rms rises); no filler may be named instead.
  expect_no_filler(run_case("magnetic_saturation", e), "magnetic_saturation");
}

TEST(ResidualDrop, CleanDropWithSpinRecordAddsNothing) {
  // With a spin-speed record through the drop the contact-geometry candidates (runout,
  // support compliance) are testable; on a clean drop none may be added.
  const auto o = run_case("clean_tach", {}, true);
  EXPECT_EQ(o.verdict, "none");
  EXPECT_TRUE(o.drop_runout.testable) << o.drop_runout.why_not;
  EXPECT_TRUE(o.compliance.testable) << o.compliance.why_not;
}

TEST(ResidualDrop, AuxSupportComplianceIsFound) {
  // A soft support (5e6 N/m, a pedestal) under aux bearing 0, in series with its contact.
  // The candidate must be found at that bearing and be beyond its noise floor; whether it is
  // kept depends on the refitted drop model (docs/residual.md). No filler may be named.
  fx::EffectSet e;
  e.aux_support = fx::AuxSupportCompliance{0, 5e6};
  const auto o = run_case("aux_support", e, true);
  for (const auto& x : o.effects_added) EXPECT_EQ(x.name, "aux_support_compliance") << "a filler was named instead";
  const hr::CandidateScore* c = nullptr;
  for (const auto& r : o.drop_ranking)
    if (r.name == "aux_support_compliance") c = &r;
  ASSERT_NE(c, nullptr);
  EXPECT_TRUE(c->testable) << c->evidence;
  EXPECT_GT(c->delta_bic, 10.0) << c->evidence;
  EXPECT_NE(c->evidence.find("aux bearing 0"), std::string::npos) << c->evidence;
  EXPECT_EQ(c->evidence.find("below the noise floor"), std::string::npos) << c->evidence;
  ASSERT_TRUE(o.compliance.testable);
  // The compliance found beyond the other bearing's: the support's 1 / k_s = 2e-7 m/N, within 30 %.
  EXPECT_NEAR(o.compliance.compliance_m_per_n[0] - o.compliance.compliance_m_per_n[1], 2e-7, 0.6e-7);
  if (o.effects_added.empty()) {
    bool listed = false;
    for (const auto& u : o.unexplained) listed = listed || (u.part == "drop" && u.kind == "contact_compliance" && u.plane == 0);
    EXPECT_TRUE(listed) << "a found but not kept support must be reported as unexplained";
  }
}

// Examples 3 and 4 of ../shared/data/synthetic (a second independent simulator) carry one
// undeclared effect each, stated in that folder's README only: the loop must name exactly
// that element. Nothing here tells the code under test which; the test compares its verdict.
TEST(ResidualDrop, SyntheticExamplesNameTheirEffect) {
  const std::pair<int, const char*> cases[] = {{3, "aux_bearing_offset"}, {4, "sensor_runout"}};
  for (const auto& [n, name] : cases) {
    const std::string path = std::string(amb::test::shared_dir()) + "/data/synthetic/bath_drop_example_" + std::to_string(n) + ".json";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
    const auto o = analyse(path);
    report("synthetic " + std::to_string(n), o);
    EXPECT_EQ(o.verdict, name) << path;
    EXPECT_LT(o.drop_after.error.statics, 0.9 * o.drop_before.error.statics) << path;
  }
}

// The two drops of ../shared/data/synthetic (an independent simulator, nothing undeclared in
// them): nothing may be added. Their truth is not read.
TEST(ResidualDrop, SyntheticExamplesAddNothing) {
  for (int n : {1, 2}) {
    const std::string path = std::string(amb::test::shared_dir()) + "/data/synthetic/bath_drop_example_" + std::to_string(n) + ".json";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
    const auto o = analyse(path);
    report("synthetic " + std::to_string(n), o);
    EXPECT_EQ(o.verdict, "none") << path;
    EXPECT_TRUE(o.drop_runout.testable) << o.drop_runout.why_not;
    // The rule that keeps fillers out: an element whose fitted parameters change nothing
    // within the recorded range is not added, however much its BIC falls. Here the currents
    // stay within about +-0.1 A, so a fitted saturation current changes the force per ampere
    // by far less than the noise; the loop must say so (earlier versions added it).
    ASSERT_TRUE(o.levitated_analysed) << o.levitated_note;
    bool saturation_ranked = false;
    for (const auto& c : o.levitated.ranking)
      if (c.name == "magnetic_saturation") {
        saturation_ranked = true;
        EXPECT_NE(c.evidence.find("no effect within the recorded range"), std::string::npos) << c.evidence;
      }
    EXPECT_TRUE(saturation_ranked);
    // What is left is reported with its structure (part, kind, plane, band or order).
    for (const auto& u : o.unexplained) {
      EXPECT_TRUE(u.part == "levitated" || u.part == "drop") << u.part;
      EXPECT_TRUE(u.plane == 0 || u.plane == 1) << u.kind;
      if (u.kind == "band") {
        EXPECT_GT(u.f_hz, 0.0);
      }
    }
  }
}

TEST(ResidualDrop, SteadyRunIsNotADropEvent) {
  const std::string path = host::generate_steady_record(temp_dir(), "not_a_drop", {});
  const auto rec = host::load_event(path);
  const auto b = board::load_board(rec.board);
  std::string why;
  EXPECT_FALSE(hr::is_drop_event(rec, b, &why));
  EXPECT_NE(why.find("trigger"), std::string::npos) << why;
  EXPECT_THROW(hr::run_drop_residual(rec, b), std::runtime_error);
}
