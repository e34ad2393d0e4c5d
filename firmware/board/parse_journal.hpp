#pragma once
// Board table [journal_bearing] (optional): a hydrodynamic journal bearing on the rig
// (seed 002) and where the AMBs place the journal in it. Host/SIL data: the firmware loop
// does not use it (the AMB controllers hold their own sensor zero).
#include "firmware/board/toml_reader.hpp"
#include "model/journal/journal_rig.hpp"

namespace amb::board {

/// `rotor_length_m` bounds the axial position. Every key range-checked; unknown keys refused.
void parse_journal_bearing(TableReader r, model::journal::JournalBearingParams& j, double rotor_length_m);

}  // namespace amb::board
