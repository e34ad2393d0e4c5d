#pragma once
// One loop-sensitivity sweep (ISO 14839-3) as the host analyses it: the board's `sweep` event
// decoded into plain arrays, one block per excited control axis. This is the contract between
// the board side (firmware generator, event, download: fills it) and the host side (H1/H2
// estimation, zone, model overlay, residual loop: reads it). Plain data, no I/O.
//
// Injection point: the standard's first option, the controller output. The excitation e (A)
// is added to the controller's current demand u_c of one axis; the amplifier receives the sum
// u = u_c + e. With the plant G (A -> m, sensor reading per current demand) and the controller
// K (m -> A, sign such that u_c = -K y), u = e / (1 + G K), so the sensitivity is S = u / e,
// the complementary sensitivity T = -u_c / e = 1 - S, and the plant G = y / u.
#include <cstdint>
#include <string>
#include <vector>

namespace amb::host::sweep {

enum class InjectionPoint : uint8_t {
  controller_output = 0,  ///< e added to the current demand (the one the firmware implements)
  sensor = 1,             ///< e added to the position reading (reserved; not implemented)
};

enum class ExcitationKind : uint8_t {
  multisine = 0,     ///< one period of `samples_per_period` samples repeated; lines at k * rate / N
  stepped_sine = 1,  ///< one line per step, `samples_per_period` samples per step period
};

/// What the generator played, as configured on the board.
struct ExcitationPlan {
  ExcitationKind kind = ExcitationKind::multisine;
  std::vector<double> frequencies_hz;  ///< excited lines, Hz (multisine: exact bins of the period)
  uint32_t samples_per_period = 0;     ///< N: loop samples per excitation period
  uint32_t settle_periods = 0;         ///< periods played before recording (transient, not stored)
  uint32_t recorded_periods = 0;       ///< P: periods stored per axis (the averages)
  double amplitude_a = 0.0;            ///< peak of e, A
  double crest_factor = 0.0;           ///< peak / rms of one period of e
};

/// One excited axis. Every vector holds recorded_periods * samples_per_period loop samples,
/// sample k at time k / rate_hz from the start of the first recorded period.
struct SweepAxisRecord {
  int axis = 0;                            ///< control axis 0..3: A axis 1, A axis 2, B axis 1, B axis 2
  std::vector<double> excitation_a;        ///< e, injected signal, A
  std::vector<double> controller_output_a; ///< u_c, the controller's demand before the summing point, A
  std::vector<double> summing_point_a;     ///< u = u_c + e, demand sent to the amplifier, A
  std::vector<double> sensor_m;            ///< y, this axis' position reading (controller frame), m
};

struct SweepRecord {
  std::string board_name;           ///< board that ran the sweep
  std::string rig_name;             ///< rig it belongs to (for the model overlay)
  double rate_hz = 0.0;             ///< loop (sample) rate, Hz
  double speed_hz = 0.0;            ///< rotor speed during the sweep, Hz (0: not spinning)
  double bias_current_a = 0.0;      ///< the AMB bias current the amplitude limit refers to, A
  double loop_delay_periods = 0.0;  ///< the board's declared loop delay, periods
  InjectionPoint injection = InjectionPoint::controller_output;
  ExcitationPlan plan;
  std::vector<SweepAxisRecord> axes;  ///< swept one after the other, in this order
  bool aborted = false;               ///< the board stopped the sweep (axes holds what completed)
  std::string abort_reason;           ///< e.g. "orbit_limit" (empty when not aborted)
};

}  // namespace amb::host::sweep
