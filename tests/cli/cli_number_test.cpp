// The one number check of the command lines (firmware/common/cli_number.hpp) and the
// translation of an options struct's field names into option names (amb-host cli_checks).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "firmware/common/cli_number.hpp"
#include "host-tools/amb-host/cli_checks.hpp"

namespace {

using amb::cli::check_number;
using amb::cli::NumberRange;

TEST(CliNumber, AcceptsFiniteNumbersInRangeWrittenInFull) {
  const NumberRange r{0.0, 10.0, false, false, "s"};
  for (const char* ok : {"0", "10", "2.5", "1e-3", "+3", "0x1p1", " 7"}) {
    double v = -1.0;
    EXPECT_EQ(check_number(ok, r, &v), "") << ok;
    EXPECT_TRUE(v >= 0.0 && v <= 10.0) << ok;
  }
}

TEST(CliNumber, RefusesWhatIsNotAFiniteNumberInRangeAndSaysWhy) {
  const NumberRange r{0.0, 10.0, true, false, "Hz"};
  const struct {
    const char* text;
    const char* why;
  } cases[] = {{"", "no value"},          {"abc", "is not a number"},     {"1e3x", "is not a number"},
               {"5 ", "is not a number"},   {"inf", "not a finite"},        {"-inf", "not a finite"},
               {"nan", "not a finite"},     {"1e400", "not a finite"},      {"0", "out of range"},
               {"-1", "out of range"},      {"10.000001", "out of range"}, {"1e9", "out of range"}};
  for (const auto& c : cases) {
    double v = 42.0;
    const std::string e = check_number(c.text, r, &v);
    EXPECT_NE(e.find(c.why), std::string::npos) << "'" << c.text << "': " << e;
    EXPECT_NE(e.find("allowed (0, 10] Hz"), std::string::npos) << e;
    EXPECT_EQ(v, 42.0) << "a refused value was stored";
  }
}

TEST(CliNumber, WholeNumbersRefuseFractions) {
  const NumberRange r{1.0, 64.0, false, true, ""};
  EXPECT_EQ(check_number("8", r), "");
  EXPECT_NE(check_number("2.5", r).find("not a whole number"), std::string::npos);
  EXPECT_NE(check_number("65", r).find("out of range"), std::string::npos);
}

TEST(CliNumber, FieldNamesBecomeOptionNamesAsWholeWordsOnly) {
  namespace hc = amb::host::cli;
  EXPECT_EQ(hc::in_option_names("stft.nfft must be a power of two", {{"stft.nfft", "--nfft"}}), "--nfft must be a power of two");
  EXPECT_EQ(hc::in_option_names("doe_points must be 2..50", {{"doe_points", "--doe"}}), "--doe must be 2..50");
  // A longer name containing the field is left alone; a trailing full stop is not part of a name.
  EXPECT_EQ(hc::in_option_names("stft.window_s and window_s.", {{"stft.window_s", "--window-s"}, {"window_s", "--window"}}),
            "--window-s and --window.");
  EXPECT_EQ(hc::in_option_names("max_window_s_extra", {{"max_window_s", "--window"}}), "max_window_s_extra");
}

}  // namespace
