#pragma once
// A complete drop event as stored: the frozen window, the metadata needed to interpret it
// without the board file, and the Phase B result. Non-real-time (owns vectors and strings).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "firmware/app/loop_sample.hpp"
#include "firmware/capture/frozen_event.hpp"
#include "firmware/capture/trigger_cause.hpp"
#include "firmware/diagnosis/phase_b.hpp"

namespace amb::board { struct BoardConfig; }

namespace amb::fw {

/// The firmware version written into every event.
inline constexpr const char* k_firmware_version = "amb-firmware 0.1.0";

struct SensorCalibration {
  double axial_m = 0.0;     ///< sensor plane from the rotor's left end, m
  double angle_deg = 0.0;   ///< measuring direction from the upward vertical, deg
};

struct ActuatorCalibration {
  double axial_m = 0.0;     ///< AMB plane from the rotor's left end, m
  double angle_deg = 0.0;   ///< actuator axis direction from the upward vertical, deg
  double ki_n_per_a = 0.0;  ///< current gain, N/A
};

struct EventMetadata {
  std::string board_name;        ///< <= 63 bytes stored
  std::string rig_name;          ///< <= 63
  std::string firmware_version;  ///< <= 31
  std::string board_source;      ///< <= 127 ("embedded:NAME" or a path)
  uint64_t event_number = 0;     ///< number in the event store (file name)
  uint64_t capture_number = 0;   ///< frozen windows since the capture was configured
  double rate_hz = 0.0;          ///< loop (sample) rate, Hz
  double pre_trigger_s = 0.0;    ///< configured pre-trigger length, s
  double post_trigger_s = 0.0;   ///< configured post-trigger length, s
  TriggerCause cause = TriggerCause::none;
  uint32_t cause_mask = 0;       ///< cause_bit() of every cause on the trigger sample
  uint8_t cutoff_channels = 0;   ///< channels the cut-off trigger saw (bit i: axis i)
  uint32_t trigger_index = 0;    ///< index of the trigger sample in `samples`
  uint32_t seq_gaps = 0;         ///< seq discontinuities seen while recording
  uint64_t trigger_seq = 0;      ///< LoopSample::seq of the trigger sample
  int64_t trigger_t_ns = 0;      ///< HAL clock time of the trigger sample, ns
  double speed_at_trigger_hz = 0.0;
  int64_t first_t_ns = 0, last_t_ns = 0;  ///< time of the first / last sample, ns
  uint64_t events_lost_before = 0;        ///< triggers lost for want of a buffer before this one
  // Controller gains in force (per axis, x/y frame).
  double kp_n_per_m = 0.0, ki_n_per_m_s = 0.0, kd_n_s_per_m = 0.0;
  double derivative_filter_hz = 0.0, integrator_limit_n = 0.0, current_limit_a = 0.0;
  std::array<SensorCalibration, 4> sensors{};     ///< [A1, A2, B1, B2]
  std::array<ActuatorCalibration, 4> actuators{}; ///< [A axis 1, A axis 2, B axis 1, B axis 2]
  double orbit_trigger_limit_m = 0.0;    ///< thresholds in force (0: trigger disabled)
  double current_trigger_limit_a = 0.0;
};

/// Quick-look load of one auxiliary bearing during the drop (bearing task, Hertz contact on
/// the rotor displacement at the aux-bearing plane; see fw::DropLoadEstimate).
struct AuxQuickLook {
  bool valid = false;                ///< false: not computed (no [bearing] table, or bad input)
  uint32_t samples_in_contact = 0;   ///< samples with the rotor beyond the clearance
  double peak_force_n = 0.0;         ///< largest contact force, N
  double peak_angle_deg = 0.0;       ///< its contact angle, deg from +x towards +y, [0, 360)
  double life_fraction = 0.0;        ///< provisional L10 life used by this drop (Miner), fraction
  double contact_time_s = 0.0;       ///< time in contact, s
};

/// What the board's analysis adds to an event (AMBE v2 section): where its speed came from,
/// how sure the speed at the trigger is, and the quick-look aux-bearing load. The host's
/// fitted wear record supersedes the quick-look once it is written back.
struct EventAnalysis {
  uint8_t speed_source = 0;              ///< fw::SpeedSource in force
  bool speed_lost_at_trigger = false;    ///< the trigger sample had no valid speed (speed_at_trigger_hz NaN)
  double speed_confidence_at_trigger = 0.0;  ///< 0..1
  bool quick_look_valid = false;         ///< the quick-look below was computed
  double quick_look_spin_hz = 0.0;       ///< aux inner-race spin used for the life fraction, Hz
  double aux_contact_constant_n_per_m1p5 = 0.0;  ///< K used, N/m^1.5
  double aux_dynamic_load_rating_n = 0.0;        ///< C used, N
  std::array<AuxQuickLook, 2> aux{};     ///< per aux bearing [rig.aux_bearing order]
};

struct EventRecord {
  EventMetadata meta;
  std::vector<LoopSample> samples;
  bool has_diagnosis = false;
  diag::Diagnosis diagnosis;
  bool has_analysis = false;   ///< AMBE v2 and v3 files always carry it; v1 files never
  EventAnalysis analysis;
  /// The AMBE version the record was decoded from (decode_event); 0 for a record built in
  /// memory (encode_event writes the current version).
  uint16_t format_version = 0;
};

/// Build the record of a frozen window: copies the samples, takes the static metadata from
/// `board`. `event_number` is the store's number for it.
EventRecord make_event_record(const FrozenEvent& e, const board::BoardConfig& board, uint64_t event_number);

/// The board-analysis section of a record: the speed source and the trigger sample's speed
/// quality; the quick-look aux-bearing load from `bearing` (configured; may be unconfigured:
/// quick_look_valid false). Non-real-time (event thread).
class BearingTask;
EventAnalysis event_analysis(const EventRecord& r, const board::BoardConfig& board, BearingTask& bearing);

/// The Phase B input of a record (samples, trigger index, rate, sensor angles).
diag::DiagnosisInput diagnosis_input(const EventRecord& r);

}  // namespace amb::fw
