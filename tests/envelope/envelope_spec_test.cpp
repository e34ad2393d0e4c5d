// Spec parsing (errors name the key) and case generation (grid order, Latin hypercube strata).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "host-tools/core/envelope/envelope_case.hpp"
#include "host-tools/core/envelope/envelope_spec.hpp"

namespace ev = amb::host::envelope;

namespace {

const char* const k_base = R"([study]
board = "bath-amb-rig"
method = "grid"
[parameters]
speed_hz = { min = 10.0, max = 30.0, points = 3 }
friction = [0.1, 0.2]
failed_channels = ["all", "A1+B2"]
)";

/// The key named by the error for `text`, or "" when it parses.
std::string error_key(const std::string& text) {
  try {
    ev::parse_spec(text, "t.toml");
  } catch (const ev::SpecError& e) {
    EXPECT_NE(std::string(e.what()).find(e.key()), std::string::npos) << e.what();
    return e.key();
  }
  return "";
}

}  // namespace

TEST(EnvelopeSpec, GridIsTheCartesianProductInFixedOrder) {
  const ev::StudySpec s = ev::parse_spec(k_base, "t.toml");
  const auto cases = ev::expand_cases(s);
  ASSERT_EQ(cases.size(), 3u * 2u * 2u);
  EXPECT_DOUBLE_EQ(cases[0].speed_hz, 10.0);
  EXPECT_DOUBLE_EQ(cases.back().speed_hz, 30.0);
  EXPECT_DOUBLE_EQ(cases[4].speed_hz, 20.0);
  EXPECT_EQ(cases[0].failed_channels, ev::k_all_channels);
  EXPECT_EQ(cases[1].failed_channels, ev::parse_channels("A1+B2"));
  EXPECT_EQ(cases[1].failed_channels, 0x9);
  const auto v = ev::varying_parameters(s);
  EXPECT_EQ(v, (std::vector<std::string>{"speed_hz", "friction", "failed_channels"}));
}

TEST(EnvelopeSpec, BadSpecsNameTheKey) {
  EXPECT_EQ(error_key(k_base), "");
  EXPECT_EQ(error_key(std::string(k_base) + "speed = 3\n"), "parameters.speed");
  EXPECT_EQ(error_key(std::string(k_base) + "clearance_m = -1.0\n"), "parameters.clearance_m");
  EXPECT_EQ(error_key("[study]\nmethod = \"random\"\n[parameters]\nspeed_hz = 1\n"), "study.method");
  EXPECT_EQ(error_key("[study]\nmethod = \"lhs\"\n[parameters]\nspeed_hz = 1\n"), "study.cases");
  EXPECT_EQ(error_key("[study]\nwindow_s = 0\n[parameters]\nspeed_hz = 1\n"), "study.window_s");
  EXPECT_EQ(error_key("[study]\n[parameters]\nfriction = 0.1\n"), "parameters.speed_hz");
  EXPECT_EQ(error_key("[study]\n[parameters]\nspeed_hz = {min = 5, max = 2}\n"), "parameters.speed_hz.max");
  EXPECT_EQ(error_key("[study]\n[parameters]\nspeed_hz = {min = 5, max = 7, step = 1}\n"), "parameters.speed_hz.step");
  EXPECT_EQ(error_key("[study]\n[parameters]\nspeed_hz = 5\nfailed_channels = [\"A1\", \"C3\"]\n"), "parameters.failed_channels[1]");
  EXPECT_EQ(error_key("[study]\n[parameters]\nspeed_hz = 5\nclearance_m = 1e-4\noffset_x_m = 2e-4\n"), "parameters.offset_x_m");
  EXPECT_EQ(error_key("[stduy]\n[parameters]\nspeed_hz = 5\n"), "stduy");
  EXPECT_EQ(error_key("[study\n"), "(syntax)");
}

TEST(EnvelopeSpec, LatinHypercubeHitsEveryStratumOnceAndIsSeeded) {
  const std::string text = R"([study]
method = "lhs"
cases = 50
seed = 7
[parameters]
speed_hz = { min = 10.0, max = 60.0 }
friction = { min = 0.0, max = 0.5 }
failed_channels = ["all", "A1"]
)";
  const ev::StudySpec s = ev::parse_spec(text, "t.toml");
  const auto a = ev::expand_cases(s);
  ASSERT_EQ(a.size(), 50u);
  std::set<int> speed_strata, friction_strata;
  int all = 0;
  for (const auto& c : a) {
    ASSERT_GE(c.speed_hz, 10.0);
    ASSERT_LT(c.speed_hz, 60.0);
    speed_strata.insert(static_cast<int>((c.speed_hz - 10.0) / 50.0 * 50.0));
    friction_strata.insert(static_cast<int>(c.friction / 0.5 * 50.0));
    all += c.failed_channels == ev::k_all_channels;
  }
  EXPECT_EQ(speed_strata.size(), 50u);
  EXPECT_EQ(friction_strata.size(), 50u);
  EXPECT_EQ(all, 25);  // a categorical parameter is stratified too: half each
  const auto b = ev::expand_cases(s);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(ev::case_hash(s.settings, a[i]), ev::case_hash(s.settings, b[i]));
  ev::StudySpec s2 = s;
  s2.seed = 8;
  const auto c = ev::expand_cases(s2);
  int same = 0;
  for (size_t i = 0; i < a.size(); ++i) same += a[i].speed_hz == c[i].speed_hz;
  EXPECT_LT(same, 5);
}

TEST(EnvelopeSpec, CaseHashChangesWithEveryParameterAndSetting) {
  ev::StudySettings st;
  ev::CaseParams c{30.0, 0.2, 1.0, 0.0, 0.0, 0.0, ev::k_all_channels};
  const std::string h = ev::case_hash(st, c);
  EXPECT_EQ(h.size(), 16u);
  std::set<std::string> seen{h};
  auto differs = [&](ev::StudySettings s2, ev::CaseParams c2) { EXPECT_TRUE(seen.insert(ev::case_hash(s2, c2)).second); };
  ev::CaseParams x = c;
  x.speed_hz = std::nextafter(30.0, 31.0);  // round-trip precision in the key
  differs(st, x);
  x = c, x.friction = 0.21, differs(st, x);
  x = c, x.unbalance_factor = 2.0, differs(st, x);
  x = c, x.clearance_m = 3e-4, differs(st, x);
  x = c, x.offset_x_m = 1e-5, differs(st, x);
  x = c, x.offset_y_m = 1e-5, differs(st, x);
  x = c, x.failed_channels = 1, differs(st, x);
  ev::StudySettings s2 = st;
  s2.window_s = 0.3, differs(s2, c);
  s2 = st, s2.board = "tum-mlps-rig", differs(s2, c);
  s2 = st, s2.contact_law = "rigid", differs(s2, c);
  EXPECT_EQ(ev::case_hash(st, c), h);
}
