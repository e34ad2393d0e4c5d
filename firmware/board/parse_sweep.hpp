#pragma once
// Parser of the board file's optional [sweep] table (see firmware/sweep/sweep_params.hpp for
// the meaning and units of every key; docs/sweep.md "Board side").
#include "firmware/board/toml_reader.hpp"
#include "firmware/sweep/sweep_params.hpp"

namespace amb::board {

/// The defaults of a board without [sweep] (or under it): SweepParams' values with a 1 s period
/// (N = rate_hz), the band kept below 0.4 x rate_hz and the abort radius inside the lifecycle's
/// fault radius.
fw::SweepParams sweep_defaults(double rate_hz, double aux_clearance_m, double max_orbit_fault_m);

/// Read [sweep] into `s` (keys absent: defaults). `rate_hz`: the loop rate (the band must lie
/// below its Nyquist frequency and hold a bin of the period). Throws BoardError naming the key.
void parse_sweep(TableReader r, fw::SweepParams& s, double rate_hz);

/// Checks of [sweep] against the rest of the board (run for defaults too): the band holds a
/// bin, the abort radius lies inside the lifecycle's fault radius. `aux_clearance_m`: the
/// smaller aux-bearing clearance; `max_orbit_fault_m`: [lifecycle] max_orbit_fault_m.
void check_sweep(const fw::SweepParams& s, double rate_hz, double aux_clearance_m, double max_orbit_fault_m,
                 const std::string& source);

}  // namespace amb::board
