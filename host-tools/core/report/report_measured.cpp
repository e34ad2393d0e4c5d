#include "host-tools/core/report/report_measured.hpp"

#include <cmath>
#include <cstdio>

#include "host-tools/core/report/report_builder.hpp"

namespace amb::host::report {

namespace {
std::string fmt(const char* f, double v) {
  char b[96];
  std::snprintf(b, sizeof b, f, v);
  return b;
}
std::string joined(const std::vector<std::string>& v, const char* none) {
  if (v.empty()) return none;
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}
}  // namespace

void add_loaded_event(ReportData& d, const LoadedEvent& e, const board::BoardConfig& board, const std::string& source) {
  const size_t n = e.samples();
  const double rate = e.sample_rate_hz;
  const size_t trig = n ? std::min(e.trigger_index, n - 1) : 0;
  d.subtitle = source;
  auto& f = d.facts.rows;
  f.clear();
  f.emplace_back("format", e.format);
  f.emplace_back("rig", e.rig);
  f.emplace_back("board", board.name + " (the rig's board: geometry, clearances, sensors)");
  f.emplace_back("window", std::to_string(n) + " samples at " + fmt("%.0f Hz", rate) + fmt(" (%.3f s before, ", trig / rate) +
                               fmt("%.3f s after the trigger)", static_cast<double>(n - trig) / rate));
  f.emplace_back("trigger", "sample " + std::to_string(trig) + fmt(" (t = %.4f s in the file)", n ? e.t_s[trig] : 0.0));
  if (e.speed_at_trigger_hz)
    f.emplace_back("speed at trigger", fmt("%.2f Hz", *e.speed_at_trigger_hz) + fmt(" (%.0f rpm)", *e.speed_at_trigger_hz * 60.0));
  else
    f.emplace_back("speed at trigger", "not recorded");
  f.emplace_back("declared faults", joined(e.declared_faults, "none declared"));
  if (!e.notes.empty()) f.emplace_back("notes in the file", e.notes);
  for (const auto& w : e.warnings) f.emplace_back("load warning", w);

  d.quick_look.unavailable("a measured event carries no board analysis: the quick-look load is computed by the board on its "
                           "own events (AMBE v2 and later)");
  d.replay.unavailable("a measured event is a recording, not a board event: it carries no firmware state to replay");
  d.cause_chain = {"declared in the recording: " + joined(e.declared_faults, "nothing"),
                   "trigger: sample " + std::to_string(trig) + " of the recording"};
  if (n == 0) return;

  // The four displacement channels in the board's sensor order.
  std::array<const LoadedChannel*, 4> sensor{};
  for (const LoadedChannel& c : e.displacement)
    if (c.rig_index >= 0 && c.rig_index < 4 && !sensor[static_cast<size_t>(c.rig_index)]) sensor[static_cast<size_t>(c.rig_index)] = &c;
  std::string missing;
  for (size_t k = 0; k < 4; ++k)
    if (!sensor[k]) missing += (missing.empty() ? "" : ", ") + std::string(k < 2 ? "A" : "B") + std::to_string(k % 2 + 1);
  if (missing.empty()) {
    std::vector<std::array<double, 4>> r_m(n);
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < 4; ++k) r_m[i][k] = sensor[k]->values[i];
    const double spin_sign = e.speed_at_trigger_hz && *e.speed_at_trigger_hz < 0.0 ? -1.0 : 1.0;
    add_orbits(d, board, r_m, trig, rate, spin_sign, source);
  } else {
    const std::string why = "the recording has no displacement channel at the board's sensor(s) " + missing +
                            " (channels are matched by axial position and angle)";
    d.orbit.unavailable(why);
    d.rubbing.unavailable(why);
  }

  if (e.speed_hz.empty()) {
    d.speed.unavailable("the recording has no speed channel");
    return;
  }
  SpeedTrace sp;
  sp.speed_label = "recorded speed";
  for (size_t i = 0; i < n && i < e.speed_hz.size(); ++i) {
    sp.t_s.push_back((static_cast<double>(i) - static_cast<double>(trig)) / rate);
    sp.speed_hz.push_back(e.speed_hz[i]);
  }
  d.speed.set(std::move(sp), source + ": the recording's speed channel");
}

}  // namespace amb::host::report
