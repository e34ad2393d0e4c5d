#pragma once
// The lifecycle around a replay. An event holds the firmware's recorded state, phase and
// fault per sample but not the operator commands nor the controller's internal state
// (integrators, derivative filters, set-point ramps): AMBE v1 has no controller snapshot.
//
//  * Commands are reconstructed from the recorded lifecycle: a transition inactive ->
//    levitating is a `levitate` taken on that sample, levitated -> spinning_up a `run`,
//    -> spinning_down/lowering without the landing input a `land`, -> fault(emergency_stop)
//    an `emergency_stop`, fault -> inactive a `reset_fault`. A command posted before step k
//    is taken in step k, exactly as on the board.
//  * A window that starts mid-run needs a warm-up: a fresh supervisor is driven with centred
//    inputs through the lifecycle (levitate, run, ...) until its state, phase and speed
//    command are those of the first recorded sample. Its controller state then differs from
//    the board's (that state is not in the event), so outputs are not expected to match
//    until the controller state is provably the same again (see event_replay.hpp).
#include <cstdint>
#include <string>

#include "firmware/app/loop_sample.hpp"
#include "firmware/app/supervisor.hpp"

namespace amb::host::replay {

/// The command that explains the recorded transition prev -> cur (Command::none if none).
fw::Command command_for_transition(const fw::LoopSample& prev, const fw::LoopSample& cur);
/// The command that brings a supervisor in the state of `prev_state/phase` to `cur` (for the
/// first replayed sample, where the previous one is the supervisor's own status).
fw::Command command_for_transition(fw::State prev_state, fw::Phase prev_phase, const fw::LoopSample& cur);

struct WarmUpResult {
  bool reached = false;       ///< supervisor in the first sample's state/phase/fault (and speed command)
  uint64_t steps = 0;         ///< supervisor steps taken
  std::string note;           ///< what was done, or why the target was not reached
};

/// Drive `sup` (freshly configured) with centred inputs until its lifecycle matches `first`.
/// `max_steps`: give up after this many steps.
WarmUpResult warm_up(fw::Supervisor& sup, const fw::LoopSample& first, uint64_t max_steps);

}  // namespace amb::host::replay
