// Board files: the shipped boards load; bad files are refused with the key and the range.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "boards/embedded_boards.hpp"
#include "firmware/board/board.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/support/read_text.hpp"

using amb::board::BoardError;
using amb::board::load_board;
using amb::board::parse_board;

namespace {

std::string bath_text() { return amb::test::read_text(std::string(amb::test::source_dir()) + "/boards/bath-amb-rig.toml"); }

// Replace the first line that starts with `key =` after `section` with `key = value`.
std::string set_key(std::string text, const std::string& section, const std::string& key,
                    const std::string& value) {
  size_t at = text.find(section);
  EXPECT_NE(at, std::string::npos) << section;
  const std::regex line("\n" + key + " = [^\n]*");
  std::smatch m;
  std::string tail = text.substr(at);
  EXPECT_TRUE(std::regex_search(tail, m, line)) << key;
  tail.replace(static_cast<size_t>(m.position(0)), static_cast<size_t>(m.length(0)), "\n" + key + " = " + value);
  return text.substr(0, at) + tail;
}

std::string error_of(const std::string& text) {
  try {
    parse_board(text, "test.toml");
  } catch (const BoardError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Board, EveryEmbeddedBoardLoads) {
  int n = 0;
  for (const auto* e = amb::boards::embedded_boards(); e->name; ++e, ++n) {
    const auto b = load_board(e->name);
    EXPECT_EQ(b.name, e->name);
    EXPECT_FALSE(b.plant.rig_name.empty());
    EXPECT_GE(b.rate_hz, 1000.0);
    EXPECT_FALSE(b.plant.rotor.elements.empty());
  }
  EXPECT_GE(n, 2);
}

TEST(Board, DefaultBoardIsEmbedded) {
  EXPECT_NO_THROW(load_board(amb::boards::k_default_board));
}

TEST(Board, FileAndEmbeddedCopyAgree) {
  const auto a = load_board("bath-amb-rig");
  const auto b = load_board(std::string(amb::test::source_dir()) + "/boards/bath-amb-rig.toml");
  EXPECT_EQ(a.controller.kp_n_per_m, b.controller.kp_n_per_m);
  EXPECT_EQ(a.plant.rotor.elements.size(), b.plant.rotor.elements.size());
}

TEST(Board, UnknownKeyIsRefusedByName) {
  std::string t = bath_text();
  t = set_key(t, "[controller]", "rate_hz", "10000.0\nkp_typo = 1.0");
  const std::string e = error_of(t);
  EXPECT_NE(e.find("controller.kp_typo"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Board, UnknownSectionIsRefused) {
  const std::string e = error_of(bath_text() + "\n[extras]\nfoo = 1\n");
  EXPECT_NE(e.find("'extras'"), std::string::npos) << e;
}

TEST(Board, OutOfRangeLoopRateNamesKeyAndRange) {
  const std::string e = error_of(set_key(bath_text(), "[controller]", "rate_hz", "50000.0"));
  EXPECT_NE(e.find("controller.rate_hz"), std::string::npos) << e;
  EXPECT_NE(e.find("[100, 40000]"), std::string::npos) << e;  // 100 Hz: slow emulated boards (tests/target)
}

TEST(Board, NegativeClearanceNamesArrayEntry) {
  const std::string e = error_of(set_key(bath_text(), "[[rig.aux_bearing]]", "clearance_m", "-0.001"));
  EXPECT_NE(e.find("rig.aux_bearing[0].clearance_m"), std::string::npos) << e;
  EXPECT_NE(e.find("out of range"), std::string::npos) << e;
}

TEST(Board, MissingFieldIsNamed) {
  std::string t = bath_text();
  const size_t at = t.find("kd_n_s_per_m");
  ASSERT_NE(at, std::string::npos);
  t.erase(at, t.find('\n', at) - at);
  const std::string e = error_of(t);
  EXPECT_NE(e.find("controller.kd_n_s_per_m"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
}

TEST(Board, WrongTypeIsRefused) {
  const std::string e = error_of(set_key(bath_text(), "[controller]", "kp_n_per_m", "\"high\""));
  EXPECT_NE(e.find("controller.kp_n_per_m"), std::string::npos) << e;
  EXPECT_NE(e.find("must be a number"), std::string::npos) << e;
}

TEST(Board, WrongNumberOfAmbsIsRefused) {
  std::string t = bath_text();
  const size_t at = t.find("[[rig.amb]]");
  t.insert(at, "[[rig.amb]]\naxial_m = 0.1\n\n");
  const std::string e = error_of(t);
  EXPECT_NE(e.find("rig.amb"), std::string::npos) << e;
}

TEST(Board, InconsistentBiasCurrentIsRefused) {
  const std::string e = error_of(set_key(bath_text(), "[[rig.amb]]", "bias_current_a", "10.0"));
  EXPECT_NE(e.find("rig.amb[0].bias_current_a"), std::string::npos) << e;
}

TEST(Board, AssumptionMustNameARealKey) {
  const std::string e = error_of(bath_text() + "\"rig.nonexistent\" = \"because\"\n");
  EXPECT_NE(e.find("rig.nonexistent"), std::string::npos) << e;
}

TEST(Board, BadTomlSyntaxGivesLine) {
  const std::string e = error_of("schema = \"amb-board/1\"\n[board\nname = 1\n");
  EXPECT_NE(e.find("line 2"), std::string::npos) << e;
}

TEST(Board, NonAsciiIsRefusedOutsideCommentsAndHarmlessInThem) {
  // toml++ 3.3 reaches __builtin_unreachable on e.g. U+00B5 while recording a key or a value
  // (fuzz_board_toml under UBSan): such text is refused with its line and column before parsing.
  const std::string base = bath_text();
  const std::string in_key = "schema = \"amb-board/1\"\n[board]\nn\xC2\xB5me = \"x\"\n";
  std::string e = error_of(in_key);
  EXPECT_NE(e.find("line 3, column 2"), std::string::npos) << e;
  EXPECT_NE(e.find("non-ASCII byte 0xC2"), std::string::npos) << e;
  // In a string value (a description in a local script would be the usual way to meet this).
  e = error_of(set_key(base, "[board]", "description", "\"Pr\xC3\xBC" "fstand\""));
  EXPECT_NE(e.find("non-ASCII"), std::string::npos) << e;
  // In comments (units, names) the file loads as before, with the same values.
  const auto plain = parse_board(base, "a.toml");
  const auto commented = parse_board("# r\xC3\xA9glage \xC2\xB5m \xC2\xB0" "C \xE3\x80\x81\n" +
                                         set_key(base, "[board]", "description", "\"x\" # 40 \xC2\xB5m '\"'"),
                                     "b.toml");
  EXPECT_EQ(commented.name, plain.name);
  EXPECT_EQ(commented.description, "x");
  EXPECT_EQ(commented.rate_hz, plain.rate_hz);
  // A '#' inside a string is not a comment: non-ASCII after it is still refused.
  e = error_of(set_key(base, "[board]", "description", "\"a # \xC2\xB5\""));
  EXPECT_NE(e.find("non-ASCII"), std::string::npos) << e;
  // A UTF-8 byte-order mark at the start is accepted.
  EXPECT_EQ(parse_board("\xEF\xBB\xBF" + base, "c.toml").name, plain.name);
}

TEST(Board, WrongSchemaIsRefused) {
  std::string t = bath_text();
  t.replace(t.find("amb-board/1"), 11, "amb-board/9");
  const std::string e = error_of(t);
  EXPECT_NE(e.find("schema"), std::string::npos) << e;
}

TEST(Board, UnknownBoardNameListsKnownOnes) {
  try {
    load_board("no-such-rig");
    FAIL();
  } catch (const BoardError& e) {
    EXPECT_NE(std::string(e.what()).find("bath-amb-rig"), std::string::npos) << e.what();
  }
}

TEST(Board, BathAssumptionsAreRecorded) {
  const auto b = load_board("bath-amb-rig");
  EXPECT_TRUE(b.assumed.count("controller.kp_n_per_m"));
}

// The speed source and the [bearing] table go through the same strict loader.
TEST(Board, SpeedSourceAndBearingTableAreChecked) {
  const std::string text = bath_text();
  EXPECT_EQ(parse_board(text, "t").tracker.speed_source, amb::fw::SpeedSource::tach) << "default";
  const std::string tracked = set_key(text, "[tracker]", "enabled", "true\nspeed_source = \"tracker\"");
  EXPECT_EQ(parse_board(tracked, "t").tracker.speed_source, amb::fw::SpeedSource::tracker);
  const std::string bad = set_key(text, "[tracker]", "enabled", "true\nspeed_source = \"radar\"");
  EXPECT_NE(error_of(bad).find("tracker.speed_source"), std::string::npos) << error_of(bad);
  const std::string off = set_key(text, "[tracker]", "enabled", "false\nspeed_source = \"tracker\"");
  EXPECT_NE(error_of(off).find("needs the tracker enabled"), std::string::npos) << error_of(off);
  const std::string frac = set_key(text, "[tracker]", "enabled", "true\ntach_disagreement_fraction = 2.0");
  EXPECT_NE(error_of(frac).find("tach_disagreement_fraction"), std::string::npos) << error_of(frac);
  const auto b = parse_board(text, "t");
  EXPECT_TRUE(b.bearing.present);
  EXPECT_FALSE(b.bearing.monitored.empty());
  const std::string unknown = set_key(text, "[bearing]", "monitored", "\"SKF 9999\"");
  EXPECT_NE(error_of(unknown).find("bearing.monitored"), std::string::npos) << error_of(unknown);
  const std::string extra = set_key(text, "[bearing]", "monitored", "\"SKF 6206\"\ncolour = \"red\"");
  EXPECT_NE(error_of(extra).find("colour"), std::string::npos) << error_of(extra);
  const std::string k = set_key(text, "[bearing]", "aux_contact_constant_n_per_m1p5", "-1.0");
  EXPECT_NE(error_of(k).find("aux_contact_constant_n_per_m1p5"), std::string::npos) << error_of(k);
}

TEST(Board, EventStoreThatHoldsNoEventIsRefused) {
  // The bath board's window: 25000 samples, 2101164 B per event file (docs/board-budget.md).
  const std::string e = error_of(set_key(bath_text(), "[capture]", "storage_capacity_bytes", "2101163"));
  EXPECT_NE(e.find("capture.storage_capacity_bytes"), std::string::npos) << e;
  EXPECT_NE(e.find("2101164 bytes"), std::string::npos) << e;
  EXPECT_TRUE(error_of(set_key(bath_text(), "[capture]", "storage_capacity_bytes", "2101164")).empty());
}
