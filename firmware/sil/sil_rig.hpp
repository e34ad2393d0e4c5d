#pragma once
// Software in the loop: the firmware's supervisor and loop runner against the `sim` HAL
// backend and a plant model built from the same board file. Not part of the firmware.
#include <functional>
#include <memory>

#include "firmware/analysis/analysis_thread.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/sample_fanout.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "hal/sim/sim_rig.hpp"
#include "model/plant/plant.hpp"
#include "model/plant/rotor_amb_plant.hpp"

namespace amb::sil {

/// How the board's analysis task (tracker, bearing task) runs in the simulation.
enum class SilAnalysis : uint8_t {
  off = 0,       ///< not at all (the speed source falls back as on a board without it)
  lockstep = 1,  ///< polled between loop periods every tracker.poll_period_s of simulated time (deterministic)
  thread = 2,    ///< its own thread, as on the board (amb-firmware --backend sim)
};

struct SilOptions {
  bool paced = false;          ///< pace to wall time instead of as fast as possible
  bool tachometer = false;     ///< give the firmware a tachometer reading
  uint64_t noise_seed = 1;     ///< seed of the plant's sensor noise
  bool start_levitated = false;///< start centred instead of resting on the touchdown bearings
  SilAnalysis analysis = SilAnalysis::off;  ///< run the analysis task (board [tracker]/[bearing])
};

/// The plant the board describes (the penalty-contact rotor-AMB plant).
std::unique_ptr<model::Plant> make_board_plant(const board::BoardConfig& board, uint64_t noise_seed);
/// The same with the plant's own options (noise seed, contact law of the plant: test-data generators).
std::unique_ptr<model::Plant> make_board_plant(const board::BoardConfig& board, const model::RotorAmbPlant::Options& options);

class SilRig {
 public:
  explicit SilRig(const board::BoardConfig& board, SilOptions options = {});
  /// Use a given plant (e.g. the non-smooth drop model); it is reset here.
  SilRig(const board::BoardConfig& board, std::unique_ptr<model::Plant> plant, SilOptions options);

  fw::Supervisor& supervisor() { return sup_; }
  fw::LoopRunner& loop() { return *loop_; }
  hal::sim::SimRig& sim() { return *sim_; }
  model::Plant& plant() { return sim_->plant(); }
  const board::BoardConfig& board() const { return board_; }
  /// The analysis task (nullptr with SilAnalysis::off).
  fw::AnalysisTask* analysis() { return analysis_.get(); }
  /// SilAnalysis::thread: wait (wall time, at most `timeout_s`) until the analysis thread has
  /// analysed every sample the loop handed over so far. An unpaced simulation runs many times
  /// faster than real time, so the thread (which polls in wall time) is behind whenever the
  /// simulation is read; this is where it catches up. What it took is returned.
  struct AnalysisDrain {
    double waited_s = 0.0;        ///< wall time waited, s
    uint64_t queued_before = 0;   ///< samples not yet analysed when the wait began
    uint64_t queued_after = 0;    ///< samples still not analysed at the end (0: caught up)
    double behind_s = 0.0;        ///< queued_before in simulated time, s
  };
  AnalysisDrain drain_analysis(double timeout_s);
  /// Route every loop sample to `sink` (nullptr: none).
  void set_sink(fw::SampleSink* sink);
  /// Called after every period (for scenario recording); may be empty.
  std::function<void(const fw::Status&)> on_period;

  double time_s() const { return static_cast<double>(sim_->time_ns()) * 1e-9; }
  /// Run for `seconds` of simulated time.
  void run_for(double seconds);
  /// Run until `done(status)` holds or `timeout_s` of simulated time passed; true if it held.
  bool run_until(const std::function<bool(const fw::Status&)>& done, double timeout_s);

 private:
  void build(std::unique_ptr<model::Plant> plant);
  void rebind();
  void periods(uint64_t n);
  board::BoardConfig board_;
  SilOptions options_;
  std::unique_ptr<hal::sim::SimRig> sim_;
  fw::Supervisor sup_;
  std::unique_ptr<fw::LoopRunner> loop_;
  fw::SampleSink* sink_ = nullptr;
  std::unique_ptr<fw::AnalysisTask> analysis_;
  fw::AnalysisThread analysis_thread_;
  fw::SampleFanout fanout_;
  uint64_t poll_every_ = 0;        ///< lockstep: periods between polls
  uint64_t since_poll_ = 0;

 public:
  ~SilRig();
};

}  // namespace amb::sil
