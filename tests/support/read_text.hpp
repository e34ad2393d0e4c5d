#pragma once
// The whole of a (text or binary) file as a string, and counts in it, for tests that look at
// what a tool wrote.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace amb::test {

/// Every byte of the file at `path`; "" if it cannot be opened.
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// How often `what` occurs in `s` (overlapping occurrences counted), e.g. elements in a page.
inline size_t count_of(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace amb::test
