#pragma once
// The HTML report of a drop-envelope study: one self-contained page (inline CSS and SVG, no
// scripts): study facts, maps of peak contact force, life fraction and whirl type over each
// pair of varied parameters (scatter maps, one mark per case), and the worst-case tables.
#include <string>

#include "host-tools/core/envelope/envelope_study.hpp"

namespace amb::host::envelope {

/// The whole page.
std::string render_envelope_report(const StudySpec& spec, const StudySummary& s);

/// Ids of the <svg> maps render_envelope_report() emits (for checks and tests).
std::vector<std::string> envelope_map_ids(const StudySpec& spec);

}  // namespace amb::host::envelope
