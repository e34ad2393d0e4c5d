// A small drop-envelope study end to end: every case simulated, case files written, a re-run
// reuses them (restartable), identical parameters give identical figures whatever the
// thread count, a torn case file is simulated again, the figures are physical (no friction
// -> no friction energy), and the report carries its maps.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/rotor/modal_reduction.hpp"
#include "host-tools/core/envelope/envelope_report.hpp"
#include "host-tools/core/envelope/envelope_study.hpp"
#include "tests/support/test_paths.hpp"

namespace ev = amb::host::envelope;
namespace fs = std::filesystem;

namespace {

// Four drops kept short (the rotor falls the 0.4 mm clearance in ~9 ms and bounces).
const char* const k_spec = R"([study]
board = "bath-amb-rig"
method = "grid"
settle_s = 0.01
window_s = 0.03
worst = 3
[parameters]
speed_hz = [20.0, 40.0]
friction = [0.0, 0.25]
)";

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("amb-envelope-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

void expect_same(const ev::CaseResult& a, const ev::CaseResult& b) {
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(a.peak_force_n[k], b.peak_force_n[k]);
    EXPECT_EQ(a.whirl[k], b.whirl[k]);
    EXPECT_EQ(a.whirl_hz[k], b.whirl_hz[k]);
    EXPECT_EQ(a.friction_energy_j[k], b.friction_energy_j[k]);
    EXPECT_EQ(a.life_fraction[k], b.life_fraction[k]);
    EXPECT_EQ(a.contact_time_s[k], b.contact_time_s[k]);
  }
  EXPECT_EQ(a.speed_end_hz, b.speed_end_hz);
}

}  // namespace

TEST(EnvelopeStudy, RunsReusesAndReportsIdenticalFigures) {
  const ev::StudySpec spec = ev::parse_spec(k_spec, "small.toml");
  const fs::path dir = fresh_dir("small");
  ev::StudyOptions o;
  o.out_dir = dir.string();
  o.threads = 2;
  size_t calls = 0;
  o.progress = [&](size_t done, size_t total) {
    ++calls;
    EXPECT_LE(done, total);
  };
  const auto builds0 = amb::model::rotor::build_counts();
  const ev::StudySummary first = ev::run_study(spec, o);
  const auto builds1 = amb::model::rotor::build_counts();
  // One rig model per study (issue 37): four cases, one FE assembly and one eigen solve.
  EXPECT_EQ(builds1.fe_builds - builds0.fe_builds, 1);
  EXPECT_EQ(builds1.eigen_solves - builds0.eigen_solves, 1);
  ASSERT_EQ(first.cases, 4u);
  EXPECT_EQ(first.cases_run, 4u);
  EXPECT_EQ(first.cases_reused, 0u);
  EXPECT_EQ(first.cases_failed, 0u);
  EXPECT_EQ(calls, 4u);
  EXPECT_GT(first.cases_per_s, 0.0);
  for (const auto& c : first.outcomes) {
    ASSERT_TRUE(c.done) << c.error;
    EXPECT_TRUE(fs::exists(ev::case_file_path(o.out_dir, c.hash)));
    // All amplifiers off: the rotor lands on its aux bearings.
    EXPECT_GT(c.result.peak_force_max_n(), 10.0) << "case " << c.index;
    EXPECT_GT(c.result.contact_time_s[0] + c.result.contact_time_s[1], 0.0);
    // Friction energy (and the life it uses) only with friction.
    if (c.params.friction == 0.0) {
      EXPECT_EQ(c.result.friction_energy_total_j(), 0.0);
      EXPECT_EQ(c.result.life_fraction_max(), 0.0);
    } else {
      EXPECT_GT(c.result.friction_energy_total_j(), 0.0);
      EXPECT_NEAR(c.result.life_fraction_max(),
                  std::max(c.result.friction_energy_j[0], c.result.friction_energy_j[1]) / spec.settings.friction_energy_budget_j,
                  1e-6 * c.result.life_fraction_max());
    }
  }
  // Worst list sorted by peak force.
  ASSERT_EQ(first.worst_force.size(), 3u);
  for (size_t i = 1; i < first.worst_force.size(); ++i)
    EXPECT_GE(first.outcomes[first.worst_force[i - 1]].result.peak_force_max_n(),
              first.outcomes[first.worst_force[i]].result.peak_force_max_n());
  ASSERT_TRUE(fs::exists(first.csv_path));
  ASSERT_TRUE(fs::exists(first.report_path));
  {
    std::ifstream f(first.csv_path);
    std::string line;
    int lines = 0;
    while (std::getline(f, line)) ++lines;
    EXPECT_EQ(lines, 5);
  }
  {
    std::ifstream f(first.report_path);
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string html = ss.str();
    const auto ids = ev::envelope_map_ids(spec);
    ASSERT_EQ(ids.size(), 3u);
    for (const auto& id : ids) EXPECT_NE(html.find("id=\"" + id + "\""), std::string::npos) << id;
    EXPECT_NE(html.find("id=\"worst-force\""), std::string::npos);
  }

  // Re-run: nothing simulated, same figures.
  const ev::StudySummary again = ev::run_study(spec, o);
  EXPECT_EQ(again.cases_run, 0u);
  EXPECT_EQ(again.cases_reused, 4u);
  EXPECT_EQ(again.cases_per_s, 0.0);
  for (size_t k = 0; k < 4; ++k) expect_same(first.outcomes[k].result, again.outcomes[k].result);

  // A torn case file and a missing one: both simulated again, to the same figures.
  const std::string torn = ev::case_file_path(o.out_dir, first.outcomes[1].hash);
  fs::resize_file(torn, fs::file_size(torn) / 2);
  fs::remove(ev::case_file_path(o.out_dir, first.outcomes[2].hash));
  const ev::StudySummary repaired = ev::run_study(spec, o);
  EXPECT_EQ(repaired.cases_run, 2u);
  EXPECT_EQ(repaired.cases_reused, 2u);
  for (size_t k = 0; k < 4; ++k) expect_same(first.outcomes[k].result, repaired.outcomes[k].result);

  // A fresh directory, one thread, in two shards: identical figures for identical cases.
  const fs::path dir2 = fresh_dir("shards");
  ev::StudyOptions s0;
  s0.out_dir = dir2.string();
  s0.threads = 1;
  s0.shard_count = 2;
  s0.write_outputs = false;
  s0.shard_index = 0;
  EXPECT_EQ(ev::run_study(spec, s0).cases_run, 2u);
  s0.shard_index = 1;
  EXPECT_EQ(ev::run_study(spec, s0).cases_run, 2u);
  ev::StudyOptions collect;
  collect.out_dir = dir2.string();
  const ev::StudySummary collected = ev::run_study(spec, collect);
  EXPECT_EQ(collected.cases_reused, 4u);
  for (size_t k = 0; k < 4; ++k) expect_same(first.outcomes[k].result, collected.outcomes[k].result);
  fs::remove_all(dir);
  fs::remove_all(dir2);
}

TEST(EnvelopeStudy, SameCaseTwiceGivesIdenticalFigures) {
  const auto board = amb::board::load_board("bath-amb-rig");
  ev::StudySettings st;
  st.settle_s = 0.01;
  st.window_s = 0.02;
  const ev::CaseParams c{35.0, 0.2, 2.0, 0.0, 2e-5, -1e-5, ev::k_all_channels};
  const ev::CaseResult a = ev::run_case(board, st, c);
  const ev::CaseResult b = ev::run_case(board, st, c);
  expect_same(a, b);
  // The JSON case file round-trips exactly.
  expect_same(a, ev::from_case_json(nlohmann::json::parse(ev::to_case_json(st, c, a).dump())));
  // An offset beyond the clearance is refused, naming it.
  ev::CaseParams bad = c;
  bad.offset_x_m = 1e-3;
  EXPECT_THROW(ev::run_case(board, st, bad), std::invalid_argument);
}

TEST(EnvelopeStudy, BadBoardIsAnError) {
  ev::StudySpec spec = ev::parse_spec(k_spec, "small.toml");
  spec.settings.board = "no-such-board";
  ev::StudyOptions o;
  o.out_dir = fresh_dir("badboard").string();
  try {
    ev::run_study(spec, o);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("study.board"), std::string::npos) << e.what();
  }
  fs::remove_all(o.out_dir);
}
