#pragma once
#include "firmware/bearing/bearing_params.hpp"
#include "firmware/board/toml_reader.hpp"

namespace amb::board {
/// [bearing]: monitored (catalogue name), radial_clearance_m, min_speed_hz, max_speed_hz,
/// aux_contact_constant_n_per_m1p5, aux_dynamic_load_rating_n, aux_spin_speed_hz.
void parse_bearing(TableReader r, fw::BearingParams& b);
}  // namespace amb::board
