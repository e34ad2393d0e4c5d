// The progress bar: silent unless its stream is a terminal or it is forced; plain lines when
// forced onto a file; never more than one line per 10 %.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "host-tools/core/ui/progress_bar.hpp"

namespace {
std::string run(bool force) {
  std::FILE* f = std::tmpfile();
  {
    amb::host::ui::ProgressBar bar("work", force, f);
    EXPECT_EQ(bar.enabled(), force);
    for (int i = 0; i <= 1000; ++i) bar.update(i / 1000.0);
    bar.finish("done");
  }
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[256];
  while (std::fgets(buf, sizeof buf, f)) s += buf;
  std::fclose(f);
  return s;
}

TEST(ProgressBar, SilentOnAFileUnlessForced) { EXPECT_TRUE(run(false).empty()); }

TEST(ProgressBar, ForcedOntoAFileWritesPlainLines) {
  const std::string s = run(true);
  size_t lines = 0;
  for (char c : s) lines += c == '\n';
  EXPECT_GE(lines, 10u);
  EXPECT_LE(lines, 12u);
  EXPECT_EQ(s.find('\r'), std::string::npos);
  EXPECT_NE(s.find("work: 100%"), std::string::npos);
  EXPECT_NE(s.find("done"), std::string::npos);
}
}  // namespace
