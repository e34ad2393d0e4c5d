#include "firmware/board/parse_capture.hpp"

#include <string>

#include "firmware/events/event_codec.hpp"

namespace amb::board {
namespace {

// Upper bound of one capture window (pre + post) in samples: a frozen event is held in RAM
// twice (ring + event buffer), so 2^22 samples of 80 bytes is ~670 MB per copy at most.
constexpr double k_max_window_samples = 4194304.0;

// Debounce and hold times: 0 (assert on the first sample) .. 10 s.
constexpr double k_max_debounce_s = 10.0;

}  // namespace

void parse_capture(TableReader r, fw::CaptureParams& c, double rate_hz) {
  c.pre_trigger_s = r.number_or("pre_trigger_s", c.pre_trigger_s, 0.0, 60.0);
  c.post_trigger_s = r.number_or("post_trigger_s", c.post_trigger_s, 1.0 / rate_hz, 600.0);
  if ((c.pre_trigger_s + c.post_trigger_s) * rate_hz > k_max_window_samples)
    r.fail("post_trigger_s", "pre_trigger_s + post_trigger_s is " +
                                 std::to_string((c.pre_trigger_s + c.post_trigger_s) * rate_hz) +
                                 " samples at the loop rate; allowed at most " +
                                 std::to_string(static_cast<long long>(k_max_window_samples)));
  c.event_buffers = static_cast<int>(r.integer_or("event_buffers", c.event_buffers, 1, 8));
  c.rearm_hold_s = r.number_or("rearm_hold_s", c.rearm_hold_s, 0.0, 600.0);
  const std::string policy = r.string_or("storage_policy", "drop_oldest");
  if (policy == "drop_oldest") c.storage_policy = fw::StoragePolicy::drop_oldest;
  else if (policy == "refuse_new") c.storage_policy = fw::StoragePolicy::refuse_new;
  else r.fail("storage_policy", "must be \"drop_oldest\" or \"refuse_new\", got \"" + policy + "\"");
  c.storage_capacity_bytes = static_cast<uint64_t>(r.integer_or(
      "storage_capacity_bytes", static_cast<long long>(c.storage_capacity_bytes), 1 << 16, 1ll << 40));
  c.max_events = static_cast<int>(r.integer_or("max_events", c.max_events, 1, 100000));
  // The byte budget must hold at least one event of this window, or every event is refused.
  const uint64_t per_event = fw::event_file_bytes(fw::capture_sizes(c, rate_hz).window_samples(), true);
  if (c.storage_capacity_bytes < per_event)
    r.fail("storage_capacity_bytes", "value " + std::to_string(c.storage_capacity_bytes) +
                                         " holds no event: one event file of this capture window (pre_trigger_s + post_trigger_s at " +
                                         std::to_string(static_cast<long long>(rate_hz)) + " Hz) is " + std::to_string(per_event) +
                                         " bytes; allowed at least that");
  c.match_axial_tolerance_m = r.number_or("match_axial_tolerance_m", c.match_axial_tolerance_m, 0.0, 1.0);
  c.match_angle_tolerance_deg = r.number_or("match_angle_tolerance_deg", c.match_angle_tolerance_deg, 0.0, 45.0);
  r.finish();
}

void parse_triggers(TableReader r, fw::TriggerParams& t) {
  const double min_debounce_s = 0.0;
  const double max_debounce_s = k_max_debounce_s;
  if (r.has("orbit")) {
    TableReader o = r.table("orbit");
    t.orbit.enabled = o.boolean_or("enabled", t.orbit.enabled);
    t.orbit.limit_m = o.number_or("limit_m", t.orbit.limit_m, 1e-6, 1e-1);
    t.orbit.hysteresis_m = o.number_or("hysteresis_m", t.orbit.hysteresis_m, 0.0, t.orbit.limit_m);
    t.orbit.debounce_s = o.number_or("debounce_s", t.orbit.debounce_s, min_debounce_s, max_debounce_s);
    o.finish();
  }
  if (r.has("current")) {
    TableReader o = r.table("current");
    t.current.enabled = o.boolean_or("enabled", t.current.enabled);
    t.current.limit_a = o.number_or("limit_a", t.current.limit_a, 1e-3, 500.0);
    t.current.hysteresis_a = o.number_or("hysteresis_a", t.current.hysteresis_a, 0.0, t.current.limit_a);
    t.current.on_saturation = o.boolean_or("on_saturation", t.current.on_saturation);
    t.current.debounce_s = o.number_or("debounce_s", t.current.debounce_s, min_debounce_s, max_debounce_s);
    o.finish();
  }
  if (r.has("cutoff")) {
    TableReader o = r.table("cutoff");
    t.cutoff.enabled = o.boolean_or("enabled", t.cutoff.enabled);
    t.cutoff.near_zero_a = o.number_or("near_zero_a", t.cutoff.near_zero_a, 0.0, 100.0);
    t.cutoff.min_demand_a = o.number_or("min_demand_a", t.cutoff.min_demand_a, 1e-3, 500.0);
    if (t.cutoff.min_demand_a <= t.cutoff.near_zero_a)
      o.fail("min_demand_a", "must be larger than near_zero_a (" + std::to_string(t.cutoff.near_zero_a) + " A)");
    t.cutoff.debounce_s = o.number_or("debounce_s", t.cutoff.debounce_s, min_debounce_s, max_debounce_s);
    o.finish();
  }
  for (const char* name : {"switch_off", "landing", "manual"}) {
    if (!r.has(name)) continue;
    TableReader o = r.table(name);
    fw::EdgeTrigger& e = std::string(name) == "switch_off" ? t.switch_off
                         : std::string(name) == "landing"  ? t.landing
                                                           : t.manual;
    e.enabled = o.boolean_or("enabled", e.enabled);
    o.finish();
  }
  if (r.has("external")) {
    TableReader o = r.table("external");
    t.external.enabled = o.boolean_or("enabled", t.external.enabled);
    t.external.debounce_s = o.number_or("debounce_s", t.external.debounce_s, min_debounce_s, max_debounce_s);
    o.finish();
  }
  r.finish();
}

}  // namespace amb::board
