#pragma once
// From a recorded capture (firmware LoopSamples) to what the replay HAL backend feeds the
// firmware (hal::replay::ReplaySample): displacements, coil currents, the read-failed flag,
// the discrete inputs (landing request, external trigger, amplifier fault) and the recorded
// speed estimate.
//
// The speed estimate: the firmware took it from a tachometer, the asynchronous tracker
// thread or its own command. The tracker cannot be re-run bit-exactly in lockstep, so the
// recorded estimate is fed back through the tachometer input; the replayed speed_hz is then
// the recorded one by construction (it is not counted as a check) and Phase B, which uses
// it, sees the same input.
#include <span>
#include <vector>

#include "firmware/app/loop_sample.hpp"
#include "hal/replay/replay_rig.hpp"

namespace amb::host::replay {

/// One ReplaySample per LoopSample (allocates; configure time).
std::vector<hal::replay::ReplaySample> replay_samples(std::span<const fw::LoopSample> recorded);

}  // namespace amb::host::replay
