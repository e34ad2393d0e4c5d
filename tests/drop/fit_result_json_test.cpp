// The fit result's JSON (host-tools/core/fit/fit_result_json.hpp): what is written reads back
// field for field; the document the command wrote before this module existed
// (tests/drop/data/fit_result_example3_v0.json: `amb-host fit
// ../shared/data/synthetic/bath_drop_example_3.json --json` of commit 0e43c0e) reads and
// re-writes to the same JSON (plus the format key); the fleet's recognition.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host-tools/core/fit/fit_result_json.hpp"
#include "tests/support/test_paths.hpp"

namespace hf = amb::host::fit;
using nlohmann::json;

namespace {

/// Every field the JSON carries set to a value of its own (not a default).
hf::FitResultDocument sample() {
  hf::FitResultDocument d;
  d.board = "bath-amb-rig";
  d.event = "ev/event_00000007.json";
  d.wear_note = "wear record sequence 3 written to w.ambw";
  hf::DropFitResult& r = d.result;
  r.friction_coefficient = 0.1875;
  r.friction_uncertainty = 0.0123;
  r.friction_method = "contact_forces";
  auto& fe = r.friction_estimate;
  fe.valid = true;
  fe.friction = 0.19;
  fe.uncertainty = 0.011;
  fe.standard_error = 0.004;
  fe.smoothing_change = -0.002;
  fe.windows_used = 7;
  fe.windows_total = 11;
  fe.window_s = 2.5e-3;
  fe.sliding_time_s = 0.0175;
  fe.measured_spin_down_rad_s2 = 210.5;
  fe.force_spin_down_rad_s2 = 205.25;
  fe.force_spin_down_scatter_rad_s2 = 3.5;
  fe.synchronous_removed = true;
  fe.synchronous_force_n = 12.5;
  fe.synchronous_moment_n_m = 0.75;
  fe.bending_modes = 2;
  fe.rotor_choice = "bent";
  fe.free_flight_samples = 33;
  fe.free_flight_force_rms_n = {4.5, 2.25};
  fe.free_flight_noise_rms_n = {1.5, 1.25};
  fe.note = "a note";
  for (int i = 0; i < 2; ++i) {
    hf::FrictionWindow w;
    w.bearing = i - 1;
    w.start_s = 0.01 * (i + 1);
    w.normal_impulse_n_s = 1.5 + i;
    w.friction_impulse_n_s = 0.3 + i;
    w.ratio = 0.2 + 0.01 * i;
    w.sliding = i == 0;
    w.next_to_rolling = i == 1;
    fe.windows.push_back(w);
  }
  r.contact_law = "hertz";
  r.contact_stiffness_n_per_m = 3.5e9;
  r.contact_damping_n_s_per_m = 2.5e3;
  r.ring_drag_n_m = 0.0625;
  r.unknowns.push_back({"friction", 0.1875, 0.0123, 0.01, 0.6, false});
  r.unknowns.push_back({"restitution", 0.6, 0.05, 0.0, 0.6, true});
  r.bound_active = true;
  for (size_t b = 0; b < 2; ++b) {
    const double k = static_cast<double>(b + 1);
    r.whirl[b] = {b ? "backward" : "bouncing", 80.5 * k, 0.01 * k, 0.4 * k, -300.0 * k, 12.0 * k};
    r.fitted_whirl[b] = {b ? "forward" : "bouncing", 70.5 * k, 0.02 * k, 0.3 * k, 250.0 * k, 10.0 * k};
    r.rubbing[b] = {0.1 * k, 0.2 * k, 0.3 * k};
    r.measured_rubbing[b] = {0.15 * k, 0.25 * k, 0.35 * k};
  }
  r.spin_down_rad_s2 = 201.0;
  r.fitted_spin_down_rad_s2 = 199.5;
  r.lock_in = {true, 0.125, 250.5, 190.25, {3.5, 4.5}, {1e-5, 2e-5}, {true, true}, true};
  r.fitted_lock_in = {true, 0.25, 240.5, 180.25, {2.5, 1.5}, {3e-5, 4e-5}, {true, true}, true};
  r.polish_evaluations = 17;
  r.restitution = 0.55;
  r.centre_offset_m = {1.5e-5, -2.5e-5};
  r.cost = {1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 31.5, true};
  r.evaluations = 123;
  r.wall_s = 4.75;
  r.converged = true;  // not consistent with bound_active: every field only needs a value of its own
  r.stop_reason = "bound active";
  r.cost_history = {40.0, 35.5, 31.5};
  r.rotor_modes_per_plane = 3;
  r.structure_trials.push_back({2, 33.5, true, false});
  r.structure_trials.push_back({3, 31.5, false, true});
  return d;
}

hf::FitResultDocument round_trip(const hf::FitResultDocument& d) {
  return hf::read_fit_result_json(json::parse(hf::fit_result_json(d).dump(2)));
}

std::filesystem::path v0_path() {
  return std::filesystem::path(amb::test::source_dir()) / "tests/drop/data/fit_result_example3_v0.json";
}

}  // namespace

TEST(FitResultJson, EveryWrittenFieldReadsBack) {
  const hf::FitResultDocument a = sample();
  const hf::FitResultDocument b = round_trip(a);
  // Written again, the read-back document is the same JSON: nothing written is lost on reading.
  EXPECT_EQ(hf::fit_result_json(b), hf::fit_result_json(a));
  EXPECT_EQ(b.board, a.board);
  EXPECT_EQ(b.event, a.event);
  EXPECT_EQ(b.wear_note, a.wear_note);
  // ... and every value written is the sample's, not a default: each leaf differs from the
  // same leaf of a default document (the sample sets every field to a value of its own).
  hf::FitResultDocument d;
  d.board = "x";
  d.event = "y";
  d.wear_note = "z";
  const json leaves = hf::fit_result_json(a).flatten();
  const json defaults = hf::fit_result_json(d).flatten();
  for (const auto& [key, value] : leaves.items()) {
    if (key == "/format" || key == "/rotor_structure/model") continue;  // constant / derived
    if (defaults.contains(key)) {
      EXPECT_NE(value, defaults[key]) << key;
    }
  }
}

TEST(FitResultJson, NotANumberIsWrittenAsNullAndReadBackAsNaN) {
  hf::FitResultDocument d = sample();
  d.result.friction_uncertainty = std::nan("");
  const json j = json::parse(hf::fit_result_json(d).dump());
  EXPECT_TRUE(j["friction_uncertainty"].is_null());
  EXPECT_TRUE(std::isnan(round_trip(d).result.friction_uncertainty));
}

TEST(FitResultJson, TheCommandsEarlierDocumentReadsAndRewritesUnchanged) {
  std::ifstream in(v0_path());
  ASSERT_TRUE(in) << v0_path();
  const json before = json::parse(in);
  ASSERT_FALSE(before.contains("format"));
  EXPECT_TRUE(hf::is_fit_result_json(before));
  const hf::FitResultDocument d = hf::read_fit_result_json(before);
  EXPECT_NEAR(d.result.friction_coefficient, 0.2032, 5e-5);
  EXPECT_EQ(d.result.friction_estimate.windows.size(), 98u);
  // Keys land in the members they name (measured and fitted differ in this document).
  const hf::DropFitResult& r = d.result;
  EXPECT_EQ(r.whirl[0].bounce_rate_per_s, before["whirl"][0]["bounce_rate_per_s"].get<double>());
  EXPECT_EQ(r.fitted_whirl[0].bounce_rate_per_s, before["fitted_whirl"][0]["bounce_rate_per_s"].get<double>());
  EXPECT_NE(r.whirl[0].bounce_rate_per_s, r.fitted_whirl[0].bounce_rate_per_s);
  EXPECT_EQ(r.rubbing[1].backward_s, before["rubbing_s_per_bearing"][1]["backward"].get<double>());
  EXPECT_EQ(r.measured_rubbing[1].forward_s, before["measured_rubbing_s_per_bearing"][1]["forward"].get<double>());
  EXPECT_EQ(r.spin_down_rad_s2, before["spin_down_rad_s2"].get<double>());
  EXPECT_EQ(r.fitted_spin_down_rad_s2, before["fitted_spin_down_rad_s2"].get<double>());
  EXPECT_EQ(r.contact_damping_n_s_per_m, before["contact_damping_n_s_per_m"].get<double>());
  ASSERT_EQ(r.unknowns.size(), before["unknowns"].size());
  EXPECT_EQ(r.unknowns[1].name, "contact_damping_n_s_per_m");
  EXPECT_EQ(r.unknowns[1].value, r.contact_damping_n_s_per_m);
  EXPECT_EQ(r.rotor_modes_per_plane, 2);
  ASSERT_EQ(r.structure_trials.size(), 2u);
  EXPECT_EQ(r.structure_trials[0].modes_per_plane, 6);
  EXPECT_EQ(r.structure_trials[1].cost, r.cost.total);
  json expected = before;
  expected["format"] = hf::k_fit_result_format;
  EXPECT_EQ(hf::fit_result_json(d), expected);
}

TEST(FitResultJson, RecognitionAndBadInput) {
  EXPECT_TRUE(hf::is_fit_result_json(hf::fit_result_json(sample())));
  EXPECT_FALSE(hf::is_fit_result_json(json{{"effects_added", json::array()}, {"friction_coefficient", 0.1}}));
  EXPECT_FALSE(hf::is_fit_result_json(json{{"format", "amb-measured-event/1"}, {"friction_coefficient", 0.1}}));
  EXPECT_FALSE(hf::is_fit_result_json(json{{"friction_coefficient", "0.1"}}));
  EXPECT_FALSE(hf::is_fit_result_json(json::array()));
  // Older, trimmed documents (as the fleet test's) read with defaults for what is absent.
  const auto d = hf::read_fit_result_json(json{{"board", "b"}, {"friction_coefficient", 0.2}});
  EXPECT_EQ(d.board, "b");
  EXPECT_EQ(d.result.friction_coefficient, 0.2);
  EXPECT_TRUE(d.result.unknowns.empty());
  const auto message = [](const json& j) {
    try {
      hf::read_fit_result_json(j);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(json{{"cost", 1.0}}).find("'friction_coefficient' missing"), std::string::npos);
  EXPECT_NE(message(json{{"friction_coefficient", 0.2}, {"converged", "yes"}}).find("'converged'"), std::string::npos);
  EXPECT_NE(message(json{{"friction_coefficient", 0.2}, {"whirl", json::array({1})}}).find("'whirl'"), std::string::npos);
  EXPECT_NE(message(json{{"format", "amb-fit-result/2"}, {"friction_coefficient", 0.2}}).find("'format'"), std::string::npos);
}
