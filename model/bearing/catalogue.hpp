#pragma once
// Named bearings with their geometry and where each number comes from.
#include <optional>
#include <span>
#include <string_view>

#include "model/bearing/geometry.hpp"

namespace amb::model::bearing {

/// All catalogue entries (static storage, never allocates).
std::span<const BearingGeometry> bearing_catalogue();

/// Look a bearing up by name. Accepts "SKF 6205", "6205", "skf6205", "6205-2RS" (case and
/// spaces ignored; a suffix after '-' is ignored). Empty if unknown.
std::optional<BearingGeometry> find_bearing(std::string_view name);

}  // namespace amb::model::bearing
