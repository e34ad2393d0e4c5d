#pragma once
// The report's self-consistency as Chromium lays it out (issue 36): a copy of the page with a
// checking script appended is rendered headless (--dump-dom); the script writes what it found
// (domCheck(), read back by chromium::dom_check) as JSON:
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
function domCheck() {
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
  return out;
}
</script>
)JS";

/// Renders `page` (an HTML report) with the checking script in headless Chromium; returns the
/// script's JSON (a discarded value when Chromium or the script failed; the test then fails).
inline nlohmann::json check_report_dom(const std::filesystem::path& page, const std::filesystem::path& work) {
  std::string log, why;
  const nlohmann::json c = chromium::dom_check(read_text(page), k_dom_check_script, work, log, why);
  EXPECT_FALSE(c.is_discarded()) << page << ": " << why << "\n" << log;
  return c;
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
