#pragma once
// The replay result as JSON (amb-host replay --json). Keys: board, mode, compare_from
// (null: none), compare_from_reason, compared_samples, mismatched_samples, bit_exact,
// warm_up {reached, steps, note, samples, differing_samples, max_demand_difference_a},
// channels [{channel, mismatches, first_index, max_abs_difference}], differences [{index,
// t_ns, t_from_trigger_s, channel, recorded, replayed, difference, ulps}], trigger {...},
// diagnosis {...}, commands_posted, wall_s.
#include <nlohmann/json.hpp>

#include "host-tools/core/replay/event_replay.hpp"

namespace amb::host::replay {

nlohmann::json to_json(const ReplayResult& r);

}  // namespace amb::host::replay
