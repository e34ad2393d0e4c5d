#pragma once
// The report's self-consistency as Chromium lays it out (issue 36): a copy of the page with a
// checking script appended is rendered headless (--dump-dom); the script writes what it found
// into <pre id="dom-check"> as JSON:
//   "figures":  name -> the distinct values it is quoted with anywhere in a table (figure
//               table and sections); one value each when the page agrees with itself;
//   "clipped":  <text> elements of an <svg> whose box is not inside the <svg> (clipped captions,
//               legends, tick labels);
//   "notes_numbers": Notes items that quote a force in N (figures belong in the Figures table);
//   "log_plots_without_ticks": log-y plots with fewer than two y tick labels;
//   "cause_chain": the cause-chain line's text.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/headless_chromium.hpp"
#include "tests/support/read_text.hpp"

namespace amb::test {

inline const char* k_dom_check_script = R"JS(
<script>
window.addEventListener('load', () => {
  const out = {figures: {}, clipped: [], notes_numbers: [], log_plots_without_ticks: [], cause_chain: ''};
  for (const tr of document.querySelectorAll('table.facts tr')) {
    const th = tr.querySelector('th'), td = tr.querySelector('td');
    if (!th || !td) continue;
    const name = th.textContent.trim();
    (out.figures[name] = out.figures[name] || []);
    const v = td.textContent.trim();
    if (!out.figures[name].includes(v)) out.figures[name].push(v);
  }
  for (const svg of document.querySelectorAll('svg')) {
    const box = svg.getBoundingClientRect();
    for (const t of svg.querySelectorAll('text')) {
      const r = t.getBoundingClientRect();
      if (r.width === 0 && r.height === 0) continue;
      if (r.left < box.left - 0.5 || r.right > box.right + 0.5 || r.top < box.top - 0.5 || r.bottom > box.bottom + 0.5)
        out.clipped.push((svg.id || '(svg)') + ': "' + t.textContent + '"');
    }
    if (svg.dataset.logY === '1') {
      const labels = [...svg.querySelectorAll('text.ytick')];
      if (labels.length < 2) out.log_plots_without_ticks.push(svg.id);
    }
  }
  for (const li of document.querySelectorAll('#notes li'))
    if (/\d\s*N\b/.test(li.textContent)) out.notes_numbers.push(li.textContent);
  const chain = document.getElementById('cause-chain');
  if (chain) out.cause_chain = chain.textContent;
  const pre = document.createElement('pre');
  pre.id = 'dom-check';
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>
)JS";

/// Renders `page` (an HTML report) with the checking script in headless Chromium; returns the
/// script's JSON (a discarded value when Chromium or the script failed; the test then fails).
inline nlohmann::json check_report_dom(const std::filesystem::path& page, const std::filesystem::path& work) {
  namespace fs = std::filesystem;
  fs::create_directories(work);
  std::string html = read_text(page);
  const size_t end = html.rfind("</body>");
  EXPECT_NE(end, std::string::npos) << page;
  if (end == std::string::npos) return nlohmann::json::value_t::discarded;
  html.insert(end, k_dom_check_script);
  const fs::path copy = fs::absolute(work / "checked.html");
  {
    std::ofstream f(copy, std::ios::binary | std::ios::trunc);
    f << html;
  }
  const fs::path profile = fs::temp_directory_path() / ("amb-report-dom-" + std::to_string(::getpid()));
  fs::remove_all(profile);
  fs::create_directories(profile);
  const fs::path dom = work / "checked.dom.html", log = work / "chromium.log";
  const int rc = chromium::run(profile, "--dump-dom --window-size=1320,4000", "file://" + copy.string(), dom, log);
  fs::remove_all(profile);
  EXPECT_EQ(rc, 0) << chromium::slurp(log);
  const std::string out = chromium::slurp(dom);
  const size_t a = out.find("<pre id=\"dom-check\">"), b = out.find("</pre>", a);
  EXPECT_NE(a, std::string::npos) << "the checking script did not run:\n" << chromium::slurp(log);
  if (a == std::string::npos || b == std::string::npos) return nlohmann::json::value_t::discarded;
  std::string text = out.substr(a + 20, b - a - 20);
  // --dump-dom escapes &, < and > in text.
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}})
    for (size_t p = text.find(from); p != std::string::npos; p = text.find(from, p + to.size())) text.replace(p, from.size(), to);
  return nlohmann::json::parse(text, nullptr, false);
}

/// The consistency assertions on a check_report_dom result. `expect_definitions`: peak-force
/// definitions the page must show (e.g. "board quick-look", "fitted drop model (wear record)").
inline void expect_consistent_report(const nlohmann::json& c, const std::vector<std::string>& expect_definitions) {
  ASSERT_FALSE(c.is_discarded());
  int peak_names = 0;
  for (const auto& [name, values] : c["figures"].items()) {
    if (name.rfind("peak contact force", 0) == 0 || name.find(" rub ") != std::string::npos ||
        name.rfind("swinging", 0) == 0 || name.rfind("largest orbit radius", 0) == 0) {
      EXPECT_EQ(values.size(), 1u) << "'" << name << "' is quoted with different values: " << values.dump();
    }
    if (name.rfind("peak contact force", 0) == 0) ++peak_names;
  }
  for (const std::string& def : expect_definitions) {
    bool found = false;
    for (const auto& [name, values] : c["figures"].items())
      found = found || (name.rfind("peak contact force", 0) == 0 && name.find(def) != std::string::npos);
    EXPECT_TRUE(found) << "no peak contact force of definition '" << def << "' on the page";
  }
  EXPECT_GE(peak_names, static_cast<int>(expect_definitions.size()));
  // An unnamed "peak force" row would be a figure without a definition.
  for (const auto& [name, values] : c["figures"].items())
    EXPECT_FALSE(name == "peak force" || name == "peak contact force") << "a peak force without its definition: " << values.dump();
  EXPECT_TRUE(c["clipped"].empty()) << "text outside its picture: " << c["clipped"].dump(1);
  EXPECT_TRUE(c["notes_numbers"].empty()) << "Notes quote figures outside the Figures table: " << c["notes_numbers"].dump(1);
  EXPECT_TRUE(c["log_plots_without_ticks"].empty()) << c["log_plots_without_ticks"].dump();
}

}  // namespace amb::test
