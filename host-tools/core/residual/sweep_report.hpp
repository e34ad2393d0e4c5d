#pragma once
// Report pieces of the sweep residual loop: the additive JSON object "model_updating" of
// `amb-host residual --json` on a sweep, and the measured-vs-modelled FRF overlay (SVG).
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/core/residual/sweep_frf.hpp"

namespace amb::host::residual {

/// Parameters (nominal, bounds, value, at_bound), identifiability, modes (frequencies, MAC)
/// before/after, validation on held-back channels, nonlinear stretches, compared bins.
nlohmann::json sweep_update_json(const SweepOutcome& o);

/// Writes the FRF overlay SVG to `path` (whole file or nothing: written to a temporary and
/// renamed). Throws std::runtime_error naming the path when it cannot be written.
void write_sweep_overlay_svg(const SweepOutcome& o, const std::string& path);

}  // namespace amb::host::residual
