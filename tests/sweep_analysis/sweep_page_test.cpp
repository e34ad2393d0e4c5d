// The sweep report page in a real browser (headless Chromium), as tests/report checks the event
// report: every Bode/coherence plot in the DOM, no page errors, no text outside its picture
// (tick labels, legends, captions), every plot with x and y tick labels and axis titles with
// units, each legend entry's colour drawn as a trace and each trace in the legend, and the
// zone table with one row per axis quoting the zone and the band.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/core/report/sweep_page.hpp"
#include "host-tools/core/sweep/sweep_analysis.hpp"
#include "tests/support/headless_chromium.hpp"
#include "tests/support/test_paths.hpp"
#include "tests/sweep_analysis/sweep_sil.hpp"

namespace {

namespace fs = std::filesystem;
using namespace amb;

const char* k_script = R"JS(
<script>
function domCheck() {
  const out = {plots: [], clipped: [], legend_mismatch: [], few_ticks: [], no_units: [], zone_rows: []};
  for (const svg of document.querySelectorAll('svg.plot')) {
    out.plots.push(svg.id);
    const box = svg.getBoundingClientRect();
    for (const t of svg.querySelectorAll('text')) {
      const r = t.getBoundingClientRect();
      if (r.width === 0 && r.height === 0) continue;
      if (r.left < box.left - 0.5 || r.right > box.right + 0.5 || r.top < box.top - 0.5 || r.bottom > box.bottom + 0.5)
        out.clipped.push(svg.id + ': "' + t.textContent + '"');
    }
    const legend = new Set([...svg.querySelectorAll('g.legend line')].map(l => l.getAttribute('stroke')));
    const drawn = new Set([...svg.querySelectorAll('polyline')].filter(p => !p.closest('g.legend')).map(p => p.getAttribute('stroke')));
    const a = [...legend].sort().join(','), b = [...drawn].sort().join(',');
    if (a !== b) out.legend_mismatch.push(svg.id + ': legend ' + a + ' drawn ' + b);
    if (svg.querySelectorAll('text.ytick').length < 2 || svg.querySelectorAll('text.xtick').length < 2) out.few_ticks.push(svg.id);
    const texts = [...svg.querySelectorAll('text')].map(t => t.textContent);
    if (!texts.some(s => s === 'frequency (Hz)') || !texts.some(s => /\(.+\)$/.test(s) && s !== 'frequency (Hz)'))
      out.no_units.push(svg.id);
  }
  for (const tr of document.querySelectorAll('#zone-table tr')) {
    const td = [...tr.querySelectorAll('td')].map(x => x.textContent);
    if (td.length) out.zone_rows.push(td);
  }
  return out;
}
</script>
)JS";

TEST(SweepPage, RendersInChromiumWithTicksLegendsAndZones) {
  if (!fs::exists(test::chromium::k_binary)) GTEST_SKIP() << "no Chromium (Debian package chromium)";
  const board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig.toml");
  test::SilSweepOptions o;
  o.axes = {0, 2};
  o.recorded_periods = 4;
  o.effects.amplifier_lag = model::effects::AmplifierLag{1e-4};  // so the page shows a model with an element
  const auto a = host::sweep::analyse_sweep(test::run_sil_sweep(b, o), b);
  const fs::path dir = fs::absolute(test::artefact_dir()) / "sweep_page";
  fs::create_directories(dir);
  host::report::write_sweep_page(a, (dir / "sweep.html").string());
  std::string log, why;
  const auto c = test::chromium::dom_check(host::report::render_sweep_page(a), k_script, dir, log, why);
  ASSERT_FALSE(c.is_discarded()) << why << "\n" << log;
  EXPECT_EQ(test::chromium::page_errors(log), "");
  const auto ids = host::report::sweep_plot_ids(a);
  EXPECT_EQ(ids.size(), 14u);  // 2 axes x (S, T, G magnitude and phase + coherence)
  for (const auto& id : ids) EXPECT_NE(std::find(c["plots"].begin(), c["plots"].end(), id), c["plots"].end()) << id;
  EXPECT_TRUE(c["clipped"].empty()) << c["clipped"].dump(1);
  EXPECT_TRUE(c["legend_mismatch"].empty()) << c["legend_mismatch"].dump(1);
  EXPECT_TRUE(c["few_ticks"].empty()) << c["few_ticks"].dump(1);
  EXPECT_TRUE(c["no_units"].empty()) << c["no_units"].dump(1);
  ASSERT_EQ(c["zone_rows"].size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const auto row = c["zone_rows"][i];
    EXPECT_EQ(row[0].get<std::string>(), a.zones[i].axis_name);
    EXPECT_EQ(row[1].get<std::string>(), a.zones[i].measured.zone);
    EXPECT_NE(row[2].get<std::string>().find('['), std::string::npos) << "no band in " << row.dump();
  }
  std::printf("[ RESULT ] sweep page %s: %zu plots\n", (dir / "sweep.html").string().c_str(), ids.size());
}

}  // namespace
