#pragma once
// What an input file holds, told from its first bytes (and, for TOML and JSON, its top-level
// keys), so that a command given the wrong kind of file says "this is a board file, not a
// machine profile" instead of failing on the first unknown key. Host side only.
#include <string>

namespace amb::host {

/// Kinds: "ambe" (board event), "wear-record" (AMBW), "mat" (MATLAB v5), "measured-event"
/// (amb-measured-event/1 sidecar), "hybrid-model", "json" (other JSON), "board" (board TOML:
/// [board] and [rig] tables), "profile" (amb-machine/1 TOML), "envelope-spec" ([study]
/// TOML), "toml" (other TOML), "csv", "empty", "missing", "directory", "unknown".
std::string sniff_file_kind(const std::string& path);

/// A name for a person: "a board event (AMBE)", "a board file", ...
std::string file_kind_phrase(const std::string& kind);

}  // namespace amb::host
