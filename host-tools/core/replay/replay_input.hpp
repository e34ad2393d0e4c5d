#pragma once
// From a recorded capture (firmware LoopSamples) to what the replay HAL backend feeds the
// firmware (hal::replay::ReplaySample): displacements, coil currents, the read-failed flag,
// the discrete inputs (landing request, external trigger, amplifier fault) and the recorded
// speed estimate.
//
// The speed: the rig's tachometer reading (AMBE v3 tach_hz; -1, "none", in older events)
// goes to the tachometer input as recorded. The firmware's speed estimate came from that
// tachometer, the asynchronous tracker thread or its own command; the tracker cannot be
// re-run bit-exactly in lockstep, so the replay publishes the recorded estimate (with its
// confidence and lost flag) as the tracker's update before each step (tracked_update()).
// Where the board takes the tracker, the replayed speed estimate is then the recorded one
// by construction; where it takes the tachometer or the command it is the firmware's own.
#include <span>
#include <vector>

#include "firmware/app/loop_sample.hpp"
#include "hal/replay/replay_rig.hpp"

namespace amb::host::replay {

/// One ReplaySample per LoopSample (allocates; configure time).
std::vector<hal::replay::ReplaySample> replay_samples(std::span<const fw::LoopSample> recorded);

/// The tracker update that reproduces a recorded sample's speed estimate: speed (Hz),
/// confidence (1) and lost flag, as fw::Supervisor::publish_tracked_speed takes them.
struct TrackedUpdate {
  double speed_hz = 0.0;
  double confidence = 0.0;
  bool lost = true;
};
TrackedUpdate tracked_update(const fw::LoopSample& recorded);

}  // namespace amb::host::replay
