#pragma once
// Replay a recorded event through a fresh firmware Supervisor on the `replay` HAL backend
// (hal/replay), with a fresh floating capture and Phase B, and compare with the recording.
//
// Where the comparison starts (the controller state at the first sample is not in the event:
// AMBE v1 holds no snapshot of integrators, derivative filters or set-point ramps):
//  * the window starts at configure (first sample seq == 0): the fresh supervisor's state is
//    the board's; every sample is compared bit for bit ("from_configure");
//  * otherwise the supervisor is warmed up to the first sample's lifecycle state (see
//    lifecycle_replay.hpp) and the comparison starts at the first recorded sample where the
//    amplifiers are off (state inactive or fault): from there the outputs no longer depend
//    on the controller state, and the next lift-off resets it (pid reset + weight preload),
//    so the state is provably the board's again ("after_warm_up"). A window that never
//    switches the amplifiers off is not compared bit for bit ("not_reproducible"); its
//    differences are still summarised.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "firmware/board/board.hpp"
#include "firmware/diagnosis/phase_b.hpp"
#include "firmware/events/event_record.hpp"
#include "host-tools/core/replay/lifecycle_replay.hpp"
#include "host-tools/core/replay/replay_compare.hpp"

namespace amb::host::replay {

struct ReplayOptions {
  uint64_t max_warm_up_steps = 20'000'000;  ///< give up a warm-up after this many loop periods
  size_t max_listed_differences = 20;       ///< differences kept in the report
  /// Optional progress (fraction done 0..1), called every ~1 % of the window.
  std::function<void(double)> progress;
};

/// Triggers of the recording and of the replayed capture.
struct TriggerComparison {
  bool replayed_frozen = false;         ///< the replayed capture froze a window
  size_t recorded_index = 0;            ///< trigger sample index in the recorded window
  size_t replayed_index = k_no_index;   ///< same, of the replayed capture (in the recorded window's indices)
  uint32_t recorded_cause_mask = 0, replayed_cause_mask = 0;
  std::string recorded_cause, replayed_cause;
  bool reproduced = false;              ///< same sample and same cause mask
};

/// Phase B on the recording and re-run on the replayed capture.
struct DiagnosisComparison {
  bool recorded_available = false;      ///< the event carried a Phase B result
  fw::diag::Diagnosis recorded, replayed;
  bool type_reproduced = false;         ///< same fault type
  bool bit_exact = false;               ///< every numeric field and the summary identical
  std::string first_difference;         ///< name of the first differing field (empty: none)
};

struct ReplayResult {
  std::string board;                    ///< board used (name and source)
  std::string mode;                     ///< "from_configure", "after_warm_up", "not_reproducible"
  std::string compare_from_reason;      ///< why the comparison starts where it does
  WarmUpResult warm_up;                 ///< steps 0 for from_configure
  ReplayComparison comparison;
  TriggerComparison trigger;
  DiagnosisComparison diagnosis;
  std::vector<fw::LoopSample> replayed; ///< the replayed capture, one per recorded sample
  uint64_t commands_posted = 0;         ///< reconstructed commands posted during the window
  double wall_s = 0.0;
};

/// Replay `event` with `board` (see board_for_event()). Throws std::runtime_error for an
/// event without samples or with a sample count that does not fit the board's capture.
ReplayResult replay_event(const fw::EventRecord& event, const board::BoardConfig& board, const ReplayOptions& o = {});

/// The first field where two diagnoses differ ("" if none).
std::string first_diagnosis_difference(const fw::diag::Diagnosis& a, const fw::diag::Diagnosis& b);

}  // namespace amb::host::replay
