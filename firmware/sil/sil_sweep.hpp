#pragma once
// A loop-sensitivity sweep on the simulated rig (software in the loop): the board's firmware
// (supervisor with its sweep generator, loop runner, floating capture, event writer storing in
// memory) against the board's plant. Levitate (optionally spin up), start the sweep the way the
// supervisory link does (Supervisor::request_sweep_start), run until the generator hands its
// record to the event thread, store it (polled between loop periods) and return the event file.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "hal/sim/sim_rig.hpp"

namespace amb::sil {

struct SilSweepOptions {
  uint64_t noise_seed = 1;     ///< the plant's sensor-noise seed
  bool spin = false;           ///< sweep at the operating speed instead of levitated at rest
  double timeout_s = 600.0;    ///< simulated time allowed for the sweep, s
  /// Called every `progress_every_s` of simulated time while the sweep runs (may be empty).
  std::function<void(const fw::SweepStatus&, double t_s)> progress;
  double progress_every_s = 0.5;
};

struct SilSweepOutcome {
  bool started = false;        ///< the loop took the start (not refused)
  bool stored = false;         ///< a sweep event was stored
  fw::SweepStatus status;      ///< the generator's status at the end
  std::string event_name;      ///< "event_NNNNNNNN.ambe"
  std::vector<uint8_t> event_bytes;  ///< the stored file
  std::string error;           ///< why not stored (lift-off failed, refused, timeout, storage)
};

/// The firmware and plant of one board, with the capture and event writer of a board (events
/// in memory); the pieces stay reachable for tests (plant faults, Modbus register map).
class SilSweepBench {
 public:
  explicit SilSweepBench(const board::BoardConfig& board, uint64_t noise_seed = 1);
  SilRig& rig() { return *rig_; }
  fw::Supervisor& supervisor() { return rig_->supervisor(); }
  fw::EventWriter& writer() { return *writer_; }
  hal::sim::MemoryStorage& storage() { return storage_; }

  /// Levitate from the touchdown bearings (and spin to the operating speed); false with
  /// `error` when the phase was not reached.
  bool levitate(bool spin, std::string& error);
  /// Run until the sweep has ended (its record handed over and stored by the writer, polled
  /// here) or `timeout_s` passed. Returns the outcome (started: a sweep ran at all).
  SilSweepOutcome run_sweep(double timeout_s, const SilSweepOptions& o = {});

 private:
  std::unique_ptr<SilRig> rig_;
  std::unique_ptr<fw::FloatingCapture> capture_;
  hal::sim::MemoryStorage storage_;
  std::unique_ptr<fw::EventWriter> writer_;
  board::BoardConfig board_;
  std::string last_sweep_name_;
  bool last_stored_ = false;
};

/// Levitate, start, run and store one sweep on the board's simulated rig.
SilSweepOutcome run_sil_sweep(const board::BoardConfig& board, const SilSweepOptions& o = {});

}  // namespace amb::sil
