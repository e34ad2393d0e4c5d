#pragma once
// The whole of a (text or binary) file as a string, for tests that look at what a tool wrote.
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

}  // namespace amb::test
