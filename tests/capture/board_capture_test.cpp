// The board file's [capture] and [triggers] tables: defaults, values, range checks, unknown keys.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "firmware/board/board.hpp"
#include "tests/support/test_paths.hpp"

namespace {
using amb::board::BoardError;
using amb::board::parse_board;

std::string bath_text() {
  std::ifstream in(std::string(amb::test::source_dir()) + "/boards/bath-amb-rig.toml");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The bath board with its [capture]/[triggers] tables replaced by `tables`.
std::string with_tables(const std::string& tables) {
  std::string t = bath_text();
  const auto at = t.find("\n# Floating capture");
  EXPECT_NE(at, std::string::npos);
  return t.substr(0, at) + "\n" + tables;
}

TEST(BoardCapture, BoardsCarryTheTables) {
  for (const char* name : {"bath-amb-rig", "unicamp-amb-rig"}) {
    const auto b = amb::board::load_board(name);
    EXPECT_DOUBLE_EQ(b.capture.pre_trigger_s, 0.5) << name;
    EXPECT_DOUBLE_EQ(b.capture.post_trigger_s, 2.0) << name;
    EXPECT_TRUE(b.capture.triggers.orbit.enabled);
    EXPECT_LT(b.capture.triggers.orbit.limit_m, b.lifecycle.max_orbit_fault_m) << name;
    EXPECT_LT(b.capture.triggers.current.limit_a, b.controller.current_limit_a) << name;
  }
}

TEST(BoardCapture, DefaultsWhenAbsent) {
  const auto b = parse_board(with_tables(""), "test");
  EXPECT_DOUBLE_EQ(b.capture.pre_trigger_s, 0.5);
  EXPECT_DOUBLE_EQ(b.capture.post_trigger_s, 2.0);
  EXPECT_EQ(b.capture.storage_policy, amb::fw::StoragePolicy::drop_oldest);
  EXPECT_TRUE(b.capture.triggers.manual.enabled);
}

TEST(BoardCapture, ValuesAreRead) {
  const auto b = parse_board(with_tables(R"(
[capture]
pre_trigger_s = 0.25
post_trigger_s = 1.0
storage_policy = "refuse_new"
max_events = 10
[triggers.orbit]
enabled = false
limit_m = 0.1e-3
[triggers.cutoff]
debounce_s = 5e-3
[triggers.manual]
enabled = false
)"),
                             "test");
  EXPECT_DOUBLE_EQ(b.capture.pre_trigger_s, 0.25);
  EXPECT_EQ(b.capture.storage_policy, amb::fw::StoragePolicy::refuse_new);
  EXPECT_EQ(b.capture.max_events, 10);
  EXPECT_FALSE(b.capture.triggers.orbit.enabled);
  EXPECT_DOUBLE_EQ(b.capture.triggers.orbit.limit_m, 0.1e-3);
  EXPECT_DOUBLE_EQ(b.capture.triggers.cutoff.debounce_s, 5e-3);
  EXPECT_FALSE(b.capture.triggers.manual.enabled);
}

void expect_refused(const std::string& tables, const std::string& key) {
  try {
    parse_board(with_tables(tables), "test");
    FAIL() << "accepted: " << tables;
  } catch (const BoardError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
  }
}

TEST(BoardCapture, BadValuesAndUnknownKeysAreRefused) {
  expect_refused("[capture]\npre_trigger_s = -1.0\n", "capture.pre_trigger_s");
  expect_refused("[capture]\npost_trigger_s = 0.0\n", "capture.post_trigger_s");
  expect_refused("[capture]\npre_trigger_s = 60.0\npost_trigger_s = 600.0\n", "capture.post_trigger_s");
  expect_refused("[capture]\nstorage_policy = \"keep_all\"\n", "capture.storage_policy");
  expect_refused("[capture]\nevent_buffers = 9\n", "capture.event_buffers");
  expect_refused("[capture]\npre_trigger = 0.5\n", "capture.pre_trigger");
  expect_refused("[triggers.orbit]\nlimit_m = 2.0\n", "triggers.orbit.limit_m");
  expect_refused("[triggers.orbit]\nlimit = 1e-4\n", "triggers.orbit.limit");
  expect_refused("[triggers.cutoff]\nnear_zero_a = 0.5\nmin_demand_a = 0.3\n", "triggers.cutoff.min_demand_a");
  expect_refused("[triggers.landing]\nenabled = 1\n", "triggers.landing.enabled");
  expect_refused("[triggers.vibration]\nenabled = true\n", "triggers.vibration");
}

}  // namespace
