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

/// The held-back accelerometers of the validation: measured, the board's model and the model
/// fitted on the other half. Same writing rules.
void write_sweep_validation_svg(const SweepOutcome& o, const std::string& path);

/// The excited bearing's current per sweep voltage: measured and predicted. Throws when the
/// outcome has no such check.
void write_sweep_current_loop_svg(const SweepOutcome& o, const std::string& path);

}  // namespace amb::host::residual
