// Headless Chromium for the browser tests of the generated pages (tests/report, tests/fleet):
// run it on a URL, read back what it wrote, and pick the page errors out of its log.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

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

/// What a checking script found on a page as Chromium lays it out: `script` (a <script> block
/// that defines `function domCheck()` returning its findings as an object) is inserted before
/// </body> of
/// `html`, the copy `work`/checked.html is rendered headless (--dump-dom), and the JSON is read
/// back. `log` gets Chromium's log. A discarded value when the page has no </body>, Chromium
/// failed or the script did not run; `why` then says which.
inline nlohmann::json dom_check(std::string html, const char* script, const std::filesystem::path& work, std::string& log,
                                std::string& why) {
  namespace fs = std::filesystem;
  const size_t end = html.rfind("</body>");
  if (end == std::string::npos) {
    why = "the page has no </body>";
    return nlohmann::json::value_t::discarded;
  }
  html.insert(end, std::string(script) +
                       "<script>window.addEventListener('load', () => {\n"
                       "  const pre = document.createElement('pre');\n"
                       "  pre.id = 'dom-check';\n"
                       "  pre.textContent = JSON.stringify(domCheck());\n"
                       "  document.body.appendChild(pre);\n"
                       "});</script>\n");
  fs::create_directories(work);
  const fs::path copy = fs::absolute(work / "checked.html");
  {
    std::ofstream f(copy, std::ios::binary | std::ios::trunc);
    f << html;
  }
  const fs::path profile = fs::temp_directory_path() / ("amb-dom-check-" + std::to_string(::getpid()));
  fs::remove_all(profile);
  fs::create_directories(profile);
  const fs::path dom = work / "checked.dom.html", log_path = work / "chromium.log";
  const int rc = run(profile, "--dump-dom --window-size=1320,4000", "file://" + copy.string(), dom, log_path);
  fs::remove_all(profile);
  log = slurp(log_path);
  const std::string out = slurp(dom);
  const size_t a = out.find("<pre id=\"dom-check\">"), b = out.find("</pre>", a);
  if (rc != 0 || a == std::string::npos || b == std::string::npos) {
    why = rc != 0 ? "Chromium exited with " + std::to_string(rc) : "the checking script did not run";
    return nlohmann::json::value_t::discarded;
  }
  std::string text = out.substr(a + 20, b - a - 20);
  // --dump-dom escapes &, < and > in text.
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}})
    for (size_t p = text.find(from); p != std::string::npos; p = text.find(from, p + to.size())) text.replace(p, from.size(), to);
  nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded()) why = "the script's output is not JSON: " + text;
  return j;
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
