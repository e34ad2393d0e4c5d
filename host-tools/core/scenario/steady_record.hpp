#pragma once
// Steady-state record generator (tests and the main scenario): the firmware levitates the board's plant with one model element
// switched on (model/effects/effect_plant.hpp), rests first on the aux bearings, spins up
// and holds a steady speed; the loop samples are written as a measured event
// (formats/measured-event.md) with declared_faults = []. Nothing else is passed on: the
// code under test reads only the files.
#include <cstdint>
#include <string>

#include "model/effects/effect_set.hpp"

namespace amb::host {

struct SteadyRecordOptions {
  std::string board = "bath-amb-rig";
  double rest_s = 0.3;          ///< at rest on the aux bearings before the levitate command, s
  double steady_s = 2.3;        ///< recorded at speed after the settle time, s
  double settle_s = 0.3;        ///< after reaching speed, s
  double spin_accel_hz_per_s = 100.0;
  std::uint64_t seed = 7;       ///< sensor-noise seed
  /// > 0: a drop event instead of a steady run. After the steady time all amplifier channels
  /// are cut (the plant loses its AMB forces, seed 000's drop) and this much is recorded
  /// after the cut; the record keeps only the last `steady_s` of levitation before the cut
  /// (what a capture's pre-trigger history holds: no rest segment, no spin-up) and its
  /// trigger_index is the cut sample. declared_faults stays empty. s
  double drop_s = 0.0;
  /// Scale of the board's disk unbalances in the generator's plant (the rig's truth; the host
  /// model never reads it: the residual loop solves the unbalance as an unknown), 1
  double unbalance_scale = 1.0;
  /// Give the firmware a tachometer (the rig's true spin speed; the recorded speed channel then
  /// follows the spin through a drop instead of being lost with the tracker's lock).
  bool tachometer = false;
  // The rig's truth beyond the elements (population studies: docs/residual.md). None of these
  // reaches the record or the board the host reads.
  double speed_hz = 0.0;                ///< > 0: operating speed of the run instead of the board's, Hz
  double friction_coefficient = -1.0;   ///< >= 0: both aux bearings' friction instead of the board's, 1
  double contact_exponent = 1.0;        ///< the plant's contact law: 1 linear penalty, 1.5 Hertz
  bool rigid_rotor = false;             ///< the rig's rotor without bending modes (rigid-body modes only)
  double ring_inertia_scale = 1.0;      ///< aux-bearing inner-ring inertia x this, 1
  double amplifier_bandwidth_scale = 1.0; ///< amplifier current-loop bandwidth x this (current decay after the cut), 1
  /// > 0: the firmware's lift-off settle tolerance instead of the board's (a commissioning
  /// setting the host never reads). With the Bath rig's seed-000 gains (integral time ~500 s,
  /// net proportional stiffness kp - ks = 1.2 MN/m) a static sensor offset r at standstill is
  /// read as about 3.3 r, so a runout above ~10 um never settles within the board's 35 um, m
  double settle_tolerance_m = 0.0;
};

/// Steady run or drop event (see drop_s). Writes DIR/STEM.json + DIR/STEM.csv; returns the sidecar path. Throws on a failed run.
std::string generate_steady_record(const std::string& dir, const std::string& stem,
                                   const model::effects::EffectSet& effects, const SteadyRecordOptions& o = {});

}  // namespace amb::host
