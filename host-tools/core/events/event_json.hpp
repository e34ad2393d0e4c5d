#pragma once
// JSON summaries of loaded events and Phase B results (for `--json` outputs).
#include <nlohmann/json.hpp>

#include "host-tools/core/events/loaded_event.hpp"

namespace amb::host {

/// Phase B result: fault_type, confidence, summary and the fault parameters.
nlohmann::json phase_b_json(const fw::diag::Diagnosis& d);

/// Everything but the sample values: source, format, rig, board, sample_rate_hz, samples,
/// duration_s, trigger_index, trigger_time_s, speed_at_trigger_hz, trigger_cause, channels,
/// declared_faults, phase_b, warnings, notes.
nlohmann::json event_summary_json(const LoadedEvent& e);

}  // namespace amb::host
