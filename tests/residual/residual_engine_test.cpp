// The residual loop's one keep/reject criterion (host-tools/core/residual/engine/): each
// condition on its own turns a keep into a reject, information features never decide, and
// the element catalogue covers every element the record kinds report.
#include <gtest/gtest.h>

#include <limits>

#include "host-tools/core/residual/engine/criterion.hpp"
#include "host-tools/core/residual/engine/elements.hpp"
#include "model/effects/effect_set.hpp"

namespace eng = amb::host::residual::engine;

namespace {

eng::CandidateEvidence good() {
  eng::CandidateEvidence c;
  c.element = "aux_bearing_offset";
  c.delta_ic = 50.0;
  c.effect_sigma = 12.0;
  c.decision = {{"centre", "sigma", 12.0, 1.0}, {"contact misfit", "clearance", 0.05, 0.02}};
  return c;
}

}  // namespace

TEST(ResidualEngine, KeepsWhatEarnsItsParametersAndExplainsItsEvidence) {
  const auto d = eng::decide(good(), eng::Criterion{});
  EXPECT_TRUE(d.kept) << d.reason;
  EXPECT_EQ(d.value, 50.0);
  EXPECT_EQ(d.threshold, 10.0);
}

TEST(ResidualEngine, EachConditionRejectsOnItsOwn) {
  const eng::Criterion k;
  auto c = good();
  c.delta_ic = 9.9;
  EXPECT_FALSE(eng::decide(c, k).kept);
  EXPECT_NE(eng::decide(c, k).reason.find("information-criterion"), std::string::npos);
  c = good();
  c.effect_sigma = 2.9;
  EXPECT_FALSE(eng::decide(c, k).kept);
  c = good();
  c.identified = false;
  c.not_identified = "x on its bound";
  EXPECT_NE(eng::decide(c, k).reason.find("x on its bound"), std::string::npos);
  c = good();
  c.decision[1].after = 0.0506;  // rises by 1.2 % (> 1 %)
  EXPECT_FALSE(eng::decide(c, k).kept);
  c = good();
  c.decision = {{"spectral", "dB", 2.0, 1.85}};  // falls by 7.5 % only
  EXPECT_FALSE(eng::decide(c, k).kept);
  c.delta_ic = 400.0;  // overwhelming evidence: half the improvement suffices
  EXPECT_TRUE(eng::decide(c, k).kept);
  c = good();
  c.testable = false;
  EXPECT_FALSE(eng::decide(c, k).kept);
}

TEST(ResidualEngine, InformationFeaturesNeverDecide) {
  auto c = good();
  c.information = {{"orbit rms over the first impacts", "clearance", 1.095, 1.100}, {"drop spectral error", "dB", 13.1, 16.9}};
  EXPECT_TRUE(eng::decide(c, eng::Criterion{}).kept);
}

TEST(ResidualEngine, HigherIsBetterAndFloorsAreHonoured) {
  eng::CandidateEvidence c = good();
  c.decision = {{"Pearson", "1", 0.95, 0.93, true}, {"spectral", "dB", 2.0, 1.0}};
  EXPECT_FALSE(eng::decide(c, eng::Criterion{}).kept);  // the Pearson falls by 2 %
  c.decision = {{"rest", "1", 0.01, 0.001, false, 0.02}};  // below its floor: cannot count
  EXPECT_FALSE(eng::decide(c, eng::Criterion{}).kept);
}

TEST(ResidualEngine, ARiseInsideItsSignificanceFloorDoesNotVeto) {
  // An aux-bearing centre the drop part would not call off (its floor, here 33 sigma) that
  // moves from 0.7 to 4.2 sigma beside a falling contact misfit: not a material rise. The
  // same rise past the floor, or with no floor, vetoes.
  eng::CandidateEvidence c = good();
  c.decision = {{"centre B", "sigma", 0.7, 4.2, false, 3.0, 33.0}, {"contact misfit", "clearance", 0.087, 0.023}};
  EXPECT_TRUE(eng::decide(c, eng::Criterion{}).kept) << eng::decide(c, eng::Criterion{}).reason;
  c.decision[0].after = 40.0;
  EXPECT_FALSE(eng::decide(c, eng::Criterion{}).kept);
  c.decision[0] = {"centre B", "sigma", 0.7, 4.2, false, 3.0};
  EXPECT_FALSE(eng::decide(c, eng::Criterion{}).kept);
}

TEST(ResidualEngine, CriterionSettingsAreChecked) {
  eng::Criterion k;
  EXPECT_TRUE(k.check().empty());
  k.min_relative_improvement = 1.5;
  EXPECT_NE(k.check().find("min_relative_improvement"), std::string::npos);
  k = {};
  k.min_delta_ic = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(k.check().find("min_delta_ic"), std::string::npos);
}

TEST(ResidualEngine, CatalogueNamesEveryModelElement) {
  for (int i = 0; i < amb::model::effects::k_effect_kinds; ++i) {
    const char* n = amb::model::effects::effect_name(static_cast<amb::model::effects::EffectKind>(i));
    const auto* e = eng::find_element(n);
    ASSERT_NE(e, nullptr) << n;
    EXPECT_FALSE(e->parameters.empty()) << n;
    EXPECT_FALSE(e->kinds.empty()) << n;
    for (const auto& p : e->parameters) EXPECT_LT(p.lower, p.upper) << n << " " << p.name;
  }
  ASSERT_NE(eng::find_element("journal_bearing_wear"), nullptr);
  EXPECT_EQ(eng::find_element("no_such_element"), nullptr);
  const auto* off = eng::find_element("aux_bearing_offset");
  EXPECT_TRUE(eng::within_bounds(*off, "x0_m", 50e-6));
  EXPECT_FALSE(eng::within_bounds(*off, "x0_m", 1e-3));
}
