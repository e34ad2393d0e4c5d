// Headless Chromium for the browser tests of the generated pages (tests/report, tests/fleet):
// run it on a URL, read back what it wrote, and pick the page errors out of its log.
#pragma once

#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>

#include "tests/support/read_text.hpp"

namespace amb::test::chromium {

/// The browser the tests drive (Debian package chromium).
inline const char* const k_binary = "/usr/bin/chromium";

/// The whole file as bytes ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) { return amb::test::read_text(p); }

/// Run Chromium headless on `url` with extra `args` and its own profile directory `profile`;
/// stdout to `out`, stderr to `log`; killed after 120 s. Returns the exit status (-1 if killed
/// by a signal).
inline int run(const std::filesystem::path& profile, const std::string& args, const std::string& url,
               const std::filesystem::path& out, const std::filesystem::path& log) {
  const std::string cmd = std::string("timeout 120 ") + k_binary +
                          " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                          " --disable-background-networking --disable-component-update --disable-sync"
                          " --disable-dev-shm-usage --enable-logging=stderr --v=0 --user-data-dir='" +
                          profile.string() + "' " + args + " '" + url + "' > '" + out.string() + "' 2> '" + log.string() + "'";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

/// Lines of a Chromium log that report page errors (uncaught exceptions, console errors).
inline std::string page_errors(const std::string& log) {
  std::string bad;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find("Uncaught") != std::string::npos || line.find("ERROR:CONSOLE") != std::string::npos ||
        (line.find(":CONSOLE(") != std::string::npos && line.find("rror") != std::string::npos))
      bad += line + "\n";
  return bad;
}

/// Width and height in pixels from a PNG's IHDR chunk ({0, 0} if it is not a PNG).
inline std::pair<uint32_t, uint32_t> png_size(const std::string& png) {
  if (png.size() < 24 || png.compare(1, 3, "PNG") != 0 || png.compare(12, 4, "IHDR") != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    return (static_cast<uint32_t>(static_cast<uint8_t>(png[at])) << 24) | (static_cast<uint32_t>(static_cast<uint8_t>(png[at + 1])) << 16) |
           (static_cast<uint32_t>(static_cast<uint8_t>(png[at + 2])) << 8) | static_cast<uint32_t>(static_cast<uint8_t>(png[at + 3]));
  };
  return {be32(16), be32(20)};
}

}  // namespace amb::test::chromium
