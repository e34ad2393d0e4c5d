#pragma once
// The field-bus protocol between the board and its sensor and amplifier nodes (docs/fieldbus.md).
// CANopen-style 11-bit identifiers: id = function code + node id (node id 1..127). Pure
// encode/decode functions on fixed-size frames: no allocation, no exceptions ([RT]).
#include <array>
#include <cstdint>

#include "hal/types.hpp"

namespace amb::fieldbus {

/// Function codes (the identifier is function + node id of the producing node, except the
/// board's commands, which carry the amplifier node's id as in CANopen RPDOs).
enum Function : uint16_t {
  k_position = 0x180,    ///< sensor -> board, classic: 4 x int16 displacement, 0.1 um/LSB
  k_demand = 0x200,      ///< board -> amplifier, classic: 4 x int16 current demand, 1 mA/LSB
  k_current = 0x280,     ///< amplifier -> board, classic: 4 x int16 measured coil current, 1 mA/LSB
  k_drive = 0x300,       ///< board -> amplifier: flags, sequence, speed set-point (8 bytes)
  k_amp_status = 0x380,  ///< amplifier -> board: flags, sequence, DC bus, temperature, fault code
  k_demand_fd = 0x400,   ///< board -> amplifier, CAN FD: sequence, flags, speed, 4 x int32 demand uA (24 bytes)
  k_sample_fd = 0x480,   ///< sensor -> board, CAN FD: sequence, faults, 4 x int32 nm, 4 x int32 uA, tach (48 bytes)
  k_board_status = 0x500,  ///< board -> anyone, classic: speed estimate, confidence, flags (8 bytes), periodic
  k_sweep_status = 0x580,  ///< board -> anyone, classic: loop-sensitivity sweep progress (8 bytes), while a sweep runs
  k_heartbeat = 0x700,   ///< every node: NMT state, node-specific state (2 bytes)
};

/// Flag bits of the board-status frame (byte 5).
enum BoardStatusFlags : uint8_t {
  status_speed_lost = 1u << 0,       ///< no valid speed (speed field = INT32_MIN)
  status_tracker_stale = 1u << 1,    ///< the tracker has not updated within tracker.stale_after_s
  status_below_min = 1u << 2,        ///< the track went below the tracker's stated minimum speed
  // bits 3..4: speed source (0 tach, 1 tracker, 2 command)
  status_defects_valid = 1u << 5,    ///< the bearing task's defect lines are at the tracked speed
  status_disagreement = 1u << 6,     ///< tracker/tach disagreements were counted since the previous frame
};

/// The board-status frame's content.
struct BoardStatus {
  double speed_hz = 0.0;       ///< board speed estimate, Hz; NaN when lost (encoded INT32_MIN)
  double confidence = 0.0;     ///< 0..1, 1 % resolution
  uint8_t flags = 0;           ///< BoardStatusFlags | speed source << 3
  uint8_t sequence = 0;        ///< increments with every frame
  uint8_t tracker_mode = 0;    ///< model::signal::TrackMode
};

/// The sweep-status frame's content (fw::SweepStatus, narrowed to 8 bytes).
struct SweepStatusFrame {
  uint8_t state = 0;          ///< fw::SweepState (0 idle, 1 settling, 2 recording, 3 storing)
  int8_t axis = -1;           ///< control axis excited (0..3), -1 none
  uint8_t axes_done = 0;      ///< axes recorded so far
  uint8_t axes_total = 0;     ///< axes the sweep covers
  uint16_t period = 0;        ///< period of the present axis (settle first), saturates
  uint8_t aborts = 0;         ///< sweeps aborted since configure (saturates at 255)
  uint8_t refusals = 0;       ///< starts refused (saturates at 255)
  uint8_t last_abort = 0;     ///< fw::SweepAbort (0..15)
  uint8_t last_refusal = 0;   ///< fw::SweepRefusal (0..15)
};

inline constexpr uint32_t k_node_mask = 0x7F;
inline constexpr int16_t k_invalid_i16 = INT16_MIN;   ///< classic channel value meaning "invalid"
inline constexpr int32_t k_invalid_i32 = INT32_MIN;   ///< FD channel value meaning "invalid"
inline constexpr double k_position_lsb_m = 1e-7;      ///< classic displacement resolution, m
inline constexpr double k_current_lsb_a = 1e-3;       ///< classic current resolution, A
inline constexpr double k_position_fd_lsb_m = 1e-9;   ///< FD displacement resolution, m
inline constexpr double k_current_fd_lsb_a = 1e-6;    ///< FD current resolution, A
inline constexpr double k_speed_lsb_hz = 1e-3;        ///< speed resolution, Hz

/// NMT states carried by heartbeats (CANopen values).
enum NmtState : uint8_t { nmt_boot = 0x00, nmt_stopped = 0x04, nmt_operational = 0x05, nmt_preoperational = 0x7F };

/// Drive/demand flag bits.
enum DriveFlags : uint8_t { drive_amplifiers_enabled = 1u << 0 };
/// Amplifier status flag bits (bits 4..7 reserved, must be 0).
enum AmpFlags : uint8_t { amp_enabled = 1u << 0, amp_fault = 1u << 1, amp_overtemp = 1u << 2, amp_undervolt = 1u << 3 };

/// Node ids of one bus.
struct NodeIds {
  uint8_t board = 1;
  uint8_t sensor = 2;
  uint8_t amplifier = 3;
};

enum class Kind : uint8_t { none = 0, position, current, demand, drive, amp_status, sample_fd, demand_fd, heartbeat };

/// A decoded message. Only the fields of its kind are meaningful.
struct Message {
  Kind kind = Kind::none;
  uint8_t node = 0;                           ///< node id in the identifier
  uint16_t sequence = 0;                      ///< drive, amp_status, FD frames
  uint8_t flags = 0;                          ///< DriveFlags / AmpFlags / FD sample flags
  uint32_t fault_bits = 0;                    ///< bit i: channel i invalid (positions, currents, FD sample)
  std::array<double, 4> displacement_m{};     ///< position, sample_fd
  std::array<double, 4> current_a{};          ///< current, demand, sample_fd, demand_fd
  double speed_hz = 0.0;                      ///< drive / demand_fd: set-point; sample_fd: tachometer (<0 none)
  double dc_bus_v = 0.0;                      ///< amp_status
  double temperature_c = 0.0;                 ///< amp_status
  uint16_t amp_fault_code = 0;                ///< amp_status
  uint8_t nmt_state = 0;                      ///< heartbeat
  uint8_t node_state = 0;                     ///< heartbeat: node-specific (board: fw::State)
};

/// Why a frame was not accepted.
enum class DecodeResult : uint8_t {
  ok = 0,
  foreign,     ///< not addressed to this side (other node ids / function not consumed here)
  malformed,   ///< identifier of ours but wrong length, wrong frame type, reserved bits set, ...
};

/// Which side decodes: the board consumes position/current/amp_status/sample_fd/heartbeats of
/// its nodes; the nodes (the bench plant) consume demand/drive/demand_fd/the board heartbeat.
enum class Side : uint8_t { board, nodes };

/// [RT] Decode `f` for `side`. Error frames are `foreign` (the CAN layer counts them).
DecodeResult decode(const hal::CanFrame& f, const NodeIds& ids, Side side, Message& out);

/// [RT] Encoders. Values beyond the field's range saturate; NaN encodes as invalid.
hal::CanFrame encode_position(uint8_t sensor_node, const std::array<double, 4>& displacement_m, uint32_t fault_bits);
hal::CanFrame encode_current(uint8_t amplifier_node, const std::array<double, 4>& current_a, uint32_t fault_bits);
hal::CanFrame encode_demand(uint8_t amplifier_node, const std::array<double, 4>& demand_a);
hal::CanFrame encode_drive(uint8_t amplifier_node, uint16_t sequence, bool amplifiers_enabled, double speed_hz);
hal::CanFrame encode_amp_status(uint8_t amplifier_node, uint16_t sequence, uint8_t flags, double dc_bus_v,
                                double temperature_c, uint16_t fault_code);
hal::CanFrame encode_sample_fd(uint8_t sensor_node, uint16_t sequence, const std::array<double, 4>& displacement_m,
                               const std::array<double, 4>& current_a, double tach_hz, uint32_t fault_bits);
hal::CanFrame encode_demand_fd(uint8_t amplifier_node, uint16_t sequence, bool amplifiers_enabled, double speed_hz,
                               const std::array<double, 4>& demand_a);
hal::CanFrame encode_heartbeat(uint8_t node, uint8_t nmt_state, uint8_t node_state);
/// Board status (id k_board_status + board node): i32 speed mHz (INT32_MIN: lost), u8
/// confidence %, u8 flags, u8 sequence, u8 tracker mode.
hal::CanFrame encode_board_status(uint8_t board_node, const BoardStatus& s);
/// Decode a board-status frame of `board_node`; false if it is not one (wrong id, length, type, bits).
bool decode_board_status(const hal::CanFrame& f, uint8_t board_node, BoardStatus& out);
/// Sweep status (id k_sweep_status + board node): u8 state (bits 0..3) | axis + 1 (bits 4..7,
/// 0 none), u8 axes done, u8 axes total, u16 period, u8 aborts, u8 refusals, u8 last abort
/// (bits 0..3) | last refusal (bits 4..7).
hal::CanFrame encode_sweep_status(uint8_t board_node, const SweepStatusFrame& s);
/// Decode a sweep-status frame of `board_node`; false if it is not one (id, length, type, values).
bool decode_sweep_status(const hal::CanFrame& f, uint8_t board_node, SweepStatusFrame& out);

}  // namespace amb::fieldbus
