#pragma once
// The board's `sweep` event (AMBE v4, record kind sweep: firmware/events/sweep_event.hpp,
// docs/event-format.md "Sweep events") decoded into the host's SweepRecord (sweep_record.hpp).
// Refuses, naming what is wrong, a file that is not a sweep event, a corrupted one, or one
// whose content does not describe a sweep the host can analyse.
#include <cstdint>
#include <span>
#include <string>

#include "firmware/events/sweep_event.hpp"
#include "host-tools/core/sweep/sweep_record.hpp"

namespace amb::host::sweep {

/// The record of a decoded event (lines at bin * rate / N; vectors widened to double).
SweepRecord to_sweep_record(const fw::SweepEvent& e);

/// Decode a file image into `out`. False with `error` ("sweep event: ..." + the codec's reason);
/// `out` untouched then.
bool decode_sweep_record(std::span<const uint8_t> bytes, SweepRecord& out, std::string& error);

/// Is the file at `path` a board event whose preamble says record kind `sweep`? Reads the
/// preamble only; false for anything else (a drop event, another file, an unreadable one).
bool is_sweep_event_file(const std::string& path);

/// Read and decode a file. Throws std::invalid_argument naming the file and what is wrong.
SweepRecord read_sweep_event_file(const std::string& path);

}  // namespace amb::host::sweep
