#pragma once
// The supervisory register map (docs/register-map.md): Modbus holding-register addresses,
// shared by the board (RegisterMap) and the host (amb-host fetch/writeback). Function codes 3
// and 4 read the same registers. 32- and 64-bit values span 2 or 4 registers, most
// significant word first; strings are 2 ASCII characters per register, first in the high byte.
// RO: read-only (writes answered with exception 2). RW: readable and writable.
// Checksums on the link are CRC-32C (firmware/persistence/crc32c.hpp).
// UNSAFE: writable only while the rotor rests (not levitating/running): exception 6 otherwise.
// ARMED: a command register; every write needs the arm sequence first (write [key, operation]
// to `arm`, then the command within [comms.modbus] arm_window_ms; single use): exception 1
// without it, 6 in the wrong lifecycle state, 3 for a bad value (docs/register-map.md).
#include <cstdint>

namespace amb::fw::regs {

inline constexpr uint16_t k_magic_value = 0x414D;  ///< "AM"
inline constexpr uint16_t k_map_version = 1;

// ---- identity (RO) -------------------------------------------------------------------
inline constexpr uint16_t identity = 0x0000;
inline constexpr uint16_t magic = 0x0000;              ///< k_magic_value
inline constexpr uint16_t map_version = 0x0001;        ///< k_map_version
inline constexpr uint16_t firmware_version = 0x0002;   ///< major << 8 | minor
inline constexpr uint16_t unit_id = 0x0003;
inline constexpr uint16_t loop_rate_hz = 0x0004;       ///< control loop rate, Hz
inline constexpr uint16_t wear_record_bytes = 0x0005;  ///< size of an encoded AMBW record, bytes
inline constexpr uint16_t download_block_bytes = 0x0006; ///< data bytes per download block
inline constexpr uint16_t writeback_chunk_bytes = 0x0007; ///< max data bytes per write-back chunk
inline constexpr uint16_t board_name = 0x0008;         ///< 16 registers, 32 characters
inline constexpr uint16_t identity_end = 0x0018;

// ---- state (RO) ----------------------------------------------------------------------
inline constexpr uint16_t state = 0x0100;              ///< fw::State
inline constexpr uint16_t phase = 0x0101;              ///< fw::Phase
inline constexpr uint16_t fault_reason = 0x0102;       ///< fw::FaultReason
inline constexpr uint16_t state_flags = 0x0103;        ///< bit0 rotor levitated/running (unsafe writes refused), bit1 fault latched, bit2 field-bus nodes alive
inline constexpr uint16_t step_count = 0x0104;         ///< u64, loop periods since configure
inline constexpr uint16_t time_ms = 0x0108;            ///< u32, HAL clock time of the status, ms
inline constexpr uint16_t state_end = 0x010A;

// ---- fault counters (RO, u32 each) --------------------------------------------------------
inline constexpr uint16_t faults = 0x0200;             ///< read_failures, sensor_fault_samples, saturated_steps, rejected_commands, safe_state_entries
inline constexpr uint16_t faults_end = 0x020A;

// ---- speed (RO) ------------------------------------------------------------------------
/// i32 values of a speed that is not valid (lost, stale, none) read 0x8000 0x0000 (INT32_MIN).
inline constexpr int32_t k_speed_invalid = INT32_MIN;
inline constexpr uint16_t speed_estimate_mhz = 0x0300; ///< i32, mHz, per tracker.speed_source; k_speed_invalid when lost
inline constexpr uint16_t speed_command_mhz = 0x0302;  ///< i32, mHz
inline constexpr uint16_t speed_confidence_pct = 0x0304; ///< u16, confidence of the estimate, % (0..100)
inline constexpr uint16_t speed_flags = 0x0305;        ///< bit0 estimate lost, bit1 tracker stale, bit2 tracker below its minimum, bits 3..4 speed source (0 tach, 1 tracker, 2 command), bit5 defect lines valid, bit6 tracker running
inline constexpr uint16_t tracked_speed_mhz = 0x0306;  ///< i32, mHz, the tracker's speed as the loop sees it; k_speed_invalid when lost or stale
inline constexpr uint16_t tracked_confidence_pct = 0x0308; ///< u16, %
inline constexpr uint16_t tracked_age_ms = 0x0309;     ///< u16, ms since the tracker's last update (saturates at 65535)
inline constexpr uint16_t tach_speed_mhz = 0x030A;     ///< i32, mHz; k_speed_invalid: no tachometer
inline constexpr uint16_t speed_disagreements = 0x030C; ///< u32, tracker updates off the tachometer by more than tracker.tach_disagreement_fraction
inline constexpr uint16_t speed_lost_periods = 0x030E; ///< u32, loop periods whose estimate was lost
inline constexpr uint16_t speed_end = 0x0310;

// ---- orbit (RO) ------------------------------------------------------------------------
inline constexpr uint16_t orbit_radius_nm = 0x0310;    ///< 2 x u32, per sensor plane, nm
inline constexpr uint16_t position_nm = 0x0314;        ///< 4 x i32 [xA, yA, xB, yB], nm
inline constexpr uint16_t current_demand_ma = 0x031C;  ///< 4 x i16, mA
inline constexpr uint16_t orbit_end = 0x0320;

// ---- loop statistics (RO) -----------------------------------------------------------------
inline constexpr uint16_t loop_periods = 0x0400;       ///< u64
inline constexpr uint16_t loop_overruns = 0x0404;      ///< u64
inline constexpr uint16_t loop_max_latency_ns = 0x0408;  ///< u32, ns
inline constexpr uint16_t loop_mean_latency_ns = 0x040A; ///< u32, ns
inline constexpr uint16_t loop_p99_latency_ns = 0x040C;  ///< u32, ns (histogram bin edge)
inline constexpr uint16_t loop_max_work_ns = 0x040E;     ///< u32, ns
/// The loop's delay, sample instant -> demand written (LoopStats, issue 38), u32 ns each:
/// p50, p99, p99.9 (histogram bin edges), max, mean; then the worst read, step and write.
inline constexpr uint16_t loop_delay_ns = 0x0410;        ///< 8 x u32, ns
inline constexpr uint16_t loop_end = 0x0420;

// ---- link statistics (RO, u32 each) -------------------------------------------------------
inline constexpr uint16_t can_stats = 0x0500;          ///< tx, rx, tx_dropped, rx_dropped, error_frames, bus_off_events, malformed (7 x u32)
inline constexpr uint16_t fieldbus_stats = 0x0510;     ///< samples, stale_periods, malformed, node_timeouts, amp_faults, tx_failures (6 x u32)
inline constexpr uint16_t modbus_stats = 0x0520;       ///< requests, exceptions, bad_frames, wrong_unit, connections, refused_unsafe (wrong state), illegal_address (7 x u32)
inline constexpr uint16_t stats_end = 0x052E;
/// Write access (u32 each): arms accepted, arm key mismatches, commands accepted, commands
/// refused not armed, refused in the wrong state, writes refused for a bad value, connections
/// refused (over max_clients).
inline constexpr uint16_t access_stats = 0x0530;
inline constexpr uint16_t access_end = 0x053E;
/// Event storage (u32 each): events written, refused by the storage policy, older events
/// dropped by the policy, write attempts failed, attempts that found the storage full, retries,
/// events waiting for a retry now, events lost (retry queue full), wear-record commits that
/// failed in storage.
inline constexpr uint16_t storage_stats = 0x0540;
inline constexpr uint16_t storage_end = 0x0552;

// ---- board analysis (RO): tracker task and bearing task ---------------------------------------
inline constexpr uint16_t analysis = 0x0600;
inline constexpr uint16_t analysis_updates = 0x0600;   ///< u32, tracker updates
inline constexpr uint16_t analysis_samples = 0x0602;   ///< u32, samples run through the tracker
inline constexpr uint16_t analysis_gaps = 0x0604;      ///< u32, gaps in the channel's sample sequence
inline constexpr uint16_t analysis_resets = 0x0606;    ///< u32, tracker restarts after long gaps
inline constexpr uint16_t analysis_ring_drops = 0x0608;///< u32, samples the loop could not hand over (ring full)
inline constexpr uint16_t defect_ftf_mhz = 0x060A;     ///< i32, monitored bearing's cage line at the tracked speed, mHz (k_speed_invalid: none)
inline constexpr uint16_t defect_bpfo_mhz = 0x060C;    ///< i32, outer-race line, mHz
inline constexpr uint16_t defect_bpfi_mhz = 0x060E;    ///< i32, inner-race line, mHz
inline constexpr uint16_t defect_bsf_mhz = 0x0610;     ///< i32, ball-spin line, mHz
inline constexpr uint16_t analysis_end = 0x0612;

// ---- board budget (RO): measured by the running board, and its storage budget ----------------
inline constexpr uint16_t budget = 0x0700;
inline constexpr uint16_t budget_locked_kb = 0x0700;      ///< u32, VmLck, kB
inline constexpr uint16_t budget_resident_kb = 0x0702;    ///< u32, VmRSS, kB
inline constexpr uint16_t budget_peak_resident_kb = 0x0704;///< u32, VmHWM, kB
inline constexpr uint16_t budget_loop_cpu = 0x0706;       ///< u16, loop thread CPU share, 1/10000 of one CPU (0xFFFF: not measured)
inline constexpr uint16_t budget_analysis_cpu = 0x0707;   ///< u16, analysis thread CPU share, 1/10000 (0xFFFF: not running)
inline constexpr uint16_t budget_cpu_window_s = 0x0708;   ///< u16, wall time the shares cover, s
inline constexpr uint16_t budget_start_to_ready_ms = 0x0709;///< u32, process start to READY, ms (0xFFFFFFFF: not yet)
inline constexpr uint16_t budget_event_bytes = 0x070B;    ///< u32, bytes of one event file at the board's capture window (worst case)
inline constexpr uint16_t budget_capacity_kib = 0x070D;   ///< u32, [capture] storage_capacity_bytes / 1024
inline constexpr uint16_t budget_max_events = 0x070F;     ///< u16, [capture] max_events (saturates)
inline constexpr uint16_t budget_events_kept = 0x0710;    ///< u16, events the store keeps at the worst case
inline constexpr uint16_t budget_end = 0x0711;
/// Buffer table (fw::buffer_budget, in its fixed order): [count, bytes of entry 0 (u32), ...].
inline constexpr uint16_t buffers = 0x0720;
inline constexpr uint16_t k_max_buffer_entries = 16;
inline constexpr uint16_t buffers_end = buffers + 1 + 2 * k_max_buffer_entries;

// ---- loop-sensitivity sweep (RO): progress, counters, configuration (docs/sweep.md) ---------
inline constexpr uint16_t sweep = 0x0800;
inline constexpr uint16_t sweep_state = 0x0800;        ///< u16 fw::SweepState: 0 idle, 1 settling, 2 recording, 3 storing
inline constexpr uint16_t sweep_axis = 0x0801;         ///< u16 control axis being excited (0..3), 0xFFFF none
inline constexpr uint16_t sweep_axis_index = 0x0802;   ///< u16 its position in the sweep's order, 0-based
inline constexpr uint16_t sweep_axes_total = 0x0803;   ///< u16 axes the sweep covers
inline constexpr uint16_t sweep_axes_done = 0x0804;    ///< u16 axes completely recorded in the present (or last) sweep
inline constexpr uint16_t sweep_period = 0x0805;       ///< u16 period of the present axis, 0-based (settle periods first; saturates)
inline constexpr uint16_t sweep_periods_per_axis = 0x0806; ///< u16 settle + recorded periods
inline constexpr uint16_t sweep_last_abort = 0x0807;   ///< u16 fw::SweepAbort of the last abort (0 none)
inline constexpr uint16_t sweep_last_refusal = 0x0808; ///< u16 fw::SweepRefusal of the last refusal (0 none)
inline constexpr uint16_t sweep_started = 0x0809;      ///< u32 sweeps started
inline constexpr uint16_t sweep_completed = 0x080B;    ///< u32 sweeps that recorded every axis
inline constexpr uint16_t sweep_aborts = 0x080D;       ///< u32 sweeps aborted
inline constexpr uint16_t sweep_refusals = 0x080F;     ///< u32 starts refused (every reason)
inline constexpr uint16_t sweep_events_stored = 0x0811;///< u32 sweep events stored
inline constexpr uint16_t sweep_last_event = 0x0813;   ///< u32 event number of the newest stored sweep event (0 none)
inline constexpr uint16_t sweep_config_refusal = 0x0815; ///< u16 fw::SweepRefusal the configuration alone causes (0: can run)
inline constexpr uint16_t sweep_samples_per_period = 0x0816; ///< u32 N
inline constexpr uint16_t sweep_settle_periods = 0x0818;   ///< u16
inline constexpr uint16_t sweep_recorded_periods = 0x0819; ///< u16 P
inline constexpr uint16_t sweep_lines = 0x081A;        ///< u16 excited lines
inline constexpr uint16_t sweep_axes_mask = 0x081B;    ///< u16 bit i: axis i swept
inline constexpr uint16_t sweep_f_first_mhz = 0x081C;  ///< u32 lowest line, mHz
inline constexpr uint16_t sweep_f_last_mhz = 0x081E;   ///< u32 highest line, mHz
inline constexpr uint16_t sweep_amplitude_ua = 0x0820; ///< u32 peak of the excitation, uA
inline constexpr uint16_t sweep_amplitude_limit_ua = 0x0822; ///< u32 board limit of the peak, uA
inline constexpr uint16_t sweep_crest_milli = 0x0824;  ///< u16 crest factor x 1000
inline constexpr uint16_t sweep_abort_orbit_nm = 0x0825; ///< u32 orbit radius that aborts, nm
inline constexpr uint16_t sweep_end = 0x0827;

// ---- arm (write access) --------------------------------------------------------------------
/// Write [key hi, key lo, operation] (3 registers, key = [comms.modbus] arm_key): arms that one
/// operation for arm_window_ms; the next write to a command register consumes it (accepted or
/// not). Wrong key: exception 3. Read: [armed operation (0 none), ms left (saturates), 0]; the
/// key never reads back.
inline constexpr uint16_t arm = 0x0F00;
inline constexpr uint16_t arm_end = 0x0F03;
/// Operations an arm names: 1..8 are the values of the command register, 16 event delete,
/// 17 wear-record commit.
enum ArmOperation : uint16_t {
  op_none = 0, op_levitate = 1, op_run = 2, op_land = 3, op_reset_fault = 4, op_emergency_stop = 5,
  op_capture = 6, op_sweep_start = 7, op_sweep_abort = 8, op_event_delete = 16, op_wear_commit = 17,
};

// ---- command (ARMED) ---------------------------------------------------------------------
inline constexpr uint16_t command = 0x1000;            ///< write 1 levitate, 2 run, 3 land, 4 reset fault, 5 emergency stop (fw::Command), 6 manual capture, 7 sweep start, 8 sweep abort; read: last result (0 none, 1 posted, 2 busy)
inline constexpr uint16_t k_command_capture = 6;       ///< command value: manual capture trigger
inline constexpr uint16_t k_command_sweep_start = 7;   ///< command value: start the loop-sensitivity sweep (refused, exception 6, unless levitated or at speed and not in fault)
inline constexpr uint16_t k_command_sweep_abort = 8;   ///< command value: abort a running sweep (plain control, no fault)

// ---- event list -----------------------------------------------------------------------------
inline constexpr uint16_t event_count = 0x2000;        ///< RO, stored events
inline constexpr uint16_t event_list_version = 0x2001; ///< RO, changes whenever the list changes
inline constexpr uint16_t event_browse_index = 0x2002; ///< RW, which entry 0x2003.. shows
inline constexpr uint16_t event_entry_size = 0x2003;   ///< RO, u32 bytes (0 if index out of range)
inline constexpr uint16_t event_entry_crc = 0x2005;    ///< RO, u32 CRC-32C of the file
inline constexpr uint16_t event_entry_name = 0x2007;   ///< RO, 16 registers, 32 characters
inline constexpr uint16_t event_entry_end = 0x2017;
inline constexpr uint16_t event_delete = 0x2020;       ///< ARMED (op 16), UNSAFE, write [index, crc hi, crc lo]: remove that event

// ---- event download window ------------------------------------------------------------------
inline constexpr uint16_t dl_select = 0x3000;          ///< RW, [index, crc hi, crc lo, block hi, block lo] (5 regs)
inline constexpr uint16_t dl_status = 0x3008;          ///< RO, DownloadStatus
inline constexpr uint16_t dl_valid_bytes = 0x3009;     ///< RO, bytes of this block (0..k_block_bytes)
inline constexpr uint16_t dl_block_crc = 0x300A;       ///< RO, u32 CRC-32C of this block's bytes
inline constexpr uint16_t dl_block = 0x300C;           ///< RO, u32 block number shown
inline constexpr uint16_t dl_total_bytes = 0x300E;     ///< RO, u32 size of the selected item
inline constexpr uint16_t dl_data = 0x3010;            ///< RO, block data (k_block_bytes / 2 regs)
inline constexpr uint16_t k_block_bytes = 228;         ///< dl_status..dl_data end = 8 + 114 = 122 regs: one read
inline constexpr uint16_t dl_end = dl_data + k_block_bytes / 2;
inline constexpr uint16_t k_wear_item_index = 0xFFFF;  ///< dl_select index naming the stored wear record

enum DownloadStatus : uint16_t { dl_ok = 0, dl_no_selection = 1, dl_stale = 2, dl_past_end = 3, dl_read_error = 4 };

// ---- wear-record summary (RO) -----------------------------------------------------------------
inline constexpr uint16_t wear_present = 0x4000;       ///< 0/1
inline constexpr uint16_t wear_sequence = 0x4001;      ///< u32
inline constexpr uint16_t wear_event_count = 0x4003;   ///< u32
inline constexpr uint16_t wear_record_crc = 0x4005;    ///< u32 CRC-32C of the whole encoded record
inline constexpr uint16_t wear_friction_micro = 0x4007;///< u32, last friction coefficient x 1e6
inline constexpr uint16_t wear_updated_unix_s = 0x4009;///< i64, s
inline constexpr uint16_t wear_life_ppm = 0x400D;      ///< 2 x u32, life used per aux bearing, parts per million
inline constexpr uint16_t wear_peak_force_n = 0x4011;  ///< 2 x u32, peak contact force per aux bearing, N
inline constexpr uint16_t wear_generation = 0x4015;    ///< u32, persistence generation
inline constexpr uint16_t wear_corrupt_at_start = 0x4017; ///< slots found torn/corrupt at start (0..2)
inline constexpr uint16_t wear_end = 0x4018;

// ---- write-back area ----------------------------------------------------------------------------
inline constexpr uint16_t wb_control = 0x5000;         ///< RW: write [1 begin, size hi, size lo, crc hi, crc lo] | [2 commit] (ARMED op 17, UNSAFE) | [3 abort]; read: WbSession
inline constexpr uint16_t wb_size = 0x5001;            ///< RO (set by begin), u32 bytes announced
inline constexpr uint16_t wb_crc = 0x5003;             ///< RO (set by begin), u32 CRC-32C announced
inline constexpr uint16_t wb_received = 0x5005;        ///< RO, u32 contiguous bytes received
inline constexpr uint16_t wb_result = 0x5007;          ///< RO, fw::WriteBackResult of the last commit
inline constexpr uint16_t wb_stored_sequence = 0x5008; ///< RO, u32 sequence of the stored record
inline constexpr uint16_t wb_status_end = 0x500A;
inline constexpr uint16_t wb_chunk = 0x5010;           ///< RW (write only data): [offset hi, offset lo, nbytes, data...]
inline constexpr uint16_t k_chunk_bytes = 232;         ///< 3 + 116 = 119 regs per FC16 write
inline constexpr uint16_t wb_chunk_end = wb_chunk + 3 + k_chunk_bytes / 2;

enum WbCommand : uint16_t { wb_begin = 1, wb_commit = 2, wb_abort = 3 };
enum WbSession : uint16_t { wb_idle = 0, wb_receiving = 1, wb_complete = 2 };

}  // namespace amb::fw::regs
