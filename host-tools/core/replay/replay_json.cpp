#include "host-tools/core/replay/replay_json.hpp"

namespace amb::host::replay {

namespace {
nlohmann::json index_or_null(size_t i) { return i == k_no_index ? nlohmann::json() : nlohmann::json(i); }
}  // namespace

nlohmann::json to_json(const ReplayResult& r) {
  const ReplayComparison& c = r.comparison;
  nlohmann::json j;
  j["board"] = r.board;
  j["mode"] = r.mode;
  j["compare_from"] = index_or_null(c.compare_from);
  j["compare_from_reason"] = r.compare_from_reason;
  j["compared_samples"] = c.compared_samples;
  j["mismatched_samples"] = c.mismatched_samples;
  j["bit_exact"] = c.bit_exact;
  j["warm_up"] = {{"reached", r.warm_up.reached},
                  {"steps", r.warm_up.steps},
                  {"note", r.warm_up.note},
                  {"samples", c.warm_up_samples},
                  {"differing_samples", c.warm_up_differing_samples},
                  {"max_demand_difference_a", c.warm_up_max_demand_difference_a}};
  j["channels"] = nlohmann::json::array();
  for (const ChannelSummary& ch : c.channels)
    j["channels"].push_back({{"channel", ch.channel},
                             {"mismatches", ch.mismatches},
                             {"first_index", index_or_null(ch.first_index)},
                             {"max_abs_difference", ch.max_abs_difference}});
  j["differences"] = nlohmann::json::array();
  for (const SampleDifference& d : c.differences)
    j["differences"].push_back({{"index", d.index},
                                {"t_ns", d.t_ns},
                                {"t_from_trigger_s", d.t_from_trigger_s},
                                {"channel", d.channel},
                                {"recorded", d.recorded},
                                {"replayed", d.replayed},
                                {"difference", d.difference},
                                {"ulps", d.ulps}});
  const TriggerComparison& t = r.trigger;
  j["trigger"] = {{"replayed_frozen", t.replayed_frozen},
                  {"recorded_index", t.recorded_index},
                  {"replayed_index", index_or_null(t.replayed_index)},
                  {"recorded_cause", t.recorded_cause},
                  {"replayed_cause", t.replayed_cause},
                  {"recorded_cause_mask", t.recorded_cause_mask},
                  {"replayed_cause_mask", t.replayed_cause_mask},
                  {"reproduced", t.reproduced}};
  const DiagnosisComparison& d = r.diagnosis;
  j["diagnosis"] = {{"recorded_available", d.recorded_available},
                    {"recorded_type", fw::diag::to_string(d.recorded.type)},
                    {"replayed_type", fw::diag::to_string(d.replayed.type)},
                    {"type_reproduced", d.type_reproduced},
                    {"bit_exact", d.bit_exact},
                    {"first_difference", d.first_difference},
                    {"replayed_summary", d.replayed.summary}};
  j["commands_posted"] = r.commands_posted;
  j["wall_s"] = r.wall_s;
  return j;
}

}  // namespace amb::host::replay
