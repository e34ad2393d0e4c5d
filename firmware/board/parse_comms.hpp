#pragma once
// Parser of the optional `[comms]` board-file table (see firmware/comms/comms_params.hpp).
#include "firmware/board/toml_reader.hpp"
#include "firmware/comms/comms_params.hpp"

namespace amb::board {

/// Read `[comms]` with sub-tables `can`, `gpio`, `modbus` (each optional, defaults otherwise).
/// Range-checked; unknown keys refused (throws BoardError naming the key).
void parse_comms(TableReader r, comms::CommsParams& c);

}  // namespace amb::board
