#pragma once
// Faults and load while the loop runs (issue 19), on this machine: the firmware as
// amb-firmware --backend linux wires it — supervisor and loop runner on CLOCK_MONOTONIC with
// absolute sleeps (SCHED_FIFO when permitted), field-bus front end, floating capture, event
// writer on a FileStorage, wear store, analysis thread, register map served by the libmodbus
// TCP server on 127.0.0.1 — with the sensor and amplifier nodes emulated on an in-process CAN
// bus (SimNodesBus: vcan is not available on every host kernel; the real SocketCAN path runs in
// the emulated-target test). Commands go over Modbus with the arm sequence, like an operator's.
//
// One run: levitate (storage faults: the rotor rests, so that wear-record commits are allowed),
// then a quiet window, a fault window and a recovery window of the same
// load (a manual capture every capture_period_s, a SCADA-like status poll, one wear-record
// write-back per window). Per window: the loop's wake-up latency (1 us histogram) and
// overruns. At the end: events frozen / written / refused / dropped / lost, records torn
// (every stored event decoded, the wear store re-opened from disk), and the counters that
// report the fault, read back over Modbus from the register map.
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace amb::sil::faults {

/// The faults the rig injects in its fault window.
enum class Fault : uint8_t {
  none = 0,         ///< quiet run (the fault window is a second quiet window)
  modbus_flood,     ///< many clients (more than max_clients), valid and refused requests, malformed frames
  can_errors,       ///< controller error frames and malformed frames on the field bus, every period
  can_babble,       ///< more error frames per period than the front end drains (64): samples delayed
  sensor_silent,    ///< the sensor node stops sending (no samples, no heartbeat)
  sensor_stale,     ///< the sensor node keeps its heartbeat but samples only every 20th period (stale in between)
  storage_full,     ///< the event/wear file system is full (quota at its current use): ENOSPC
  storage_full_other, ///< full with other files: less free than the events already stored
  storage_eio,      ///< every fsync fails with EIO
  storage_read_only,///< the file system went read-only: create, rename, unlink fail with EROFS
  storage_slow_fsync, ///< every fsync takes slow_fsync_ms
};
const char* to_string(Fault f);
bool parse_fault(const std::string& name, Fault& out);
std::vector<Fault> all_faults();

struct RigOptions {
  Fault fault = Fault::none;
  double window_s = 3.0;          ///< length of the quiet and of the fault window, s
  double recovery_s = 1.5;        ///< after the fault is cleared, s (longer while events are pending, bounded)
  double capture_period_s = 0.5;  ///< a manual capture (armed, over Modbus) this often, s
  int flood_clients = 12;         ///< modbus_flood: client threads (max_clients is 4)
  int flood_malformed_clients = 3;///< modbus_flood: threads sending malformed frames
  uint64_t flood_max_requests = 2'000'000;  ///< modbus_flood: bound on requests, all threads
  int can_error_frames = 8;       ///< can_errors: error frames per period (+2 malformed)
  int can_babble_frames = 100;    ///< can_babble: error frames per period
  int slow_fsync_ms = 300;        ///< storage_slow_fsync
  int max_pending = 16;           ///< the event writer's retry queue (WriterOptions::max_pending), events
  std::string dir;                ///< storage root (empty: a fresh directory under /tmp)
  bool keep_dir = false;
};

/// Wake-up latency and overruns of one window.
struct WindowStats {
  uint64_t periods = 0, overruns = 0;
  double p50_us = 0, p99_us = 0, p999_us = 0, max_us = 0, mean_us = 0;
};

struct RigResult {
  Fault fault = Fault::none;
  bool realtime = false;          ///< the loop thread got SCHED_FIFO
  bool levitated = false;         ///< the windows ran levitated (storage faults: resting, see fault_rig.cpp)
  WindowStats quiet, faulted, recovery;
  // Events.
  uint64_t captures_requested = 0, events_frozen = 0, capture_lost = 0;
  uint64_t written = 0, refused = 0, dropped_oldest = 0, write_errors = 0, retries = 0, pending_at_end = 0,
           writer_lost = 0;
  uint64_t events_lost = 0;       ///< capture_lost + writer_lost (must be 0)
  uint64_t files_on_disk = 0;
  uint64_t events_torn = 0;       ///< stored event files that do not decode (must be 0)
  int wear_corrupt_slots = 0;     ///< wear slots torn/corrupt when re-opened from disk (must be 0)
  uint32_t wear_sequence = 0;     ///< of the record on disk at the end
  std::vector<std::string> writebacks;  ///< result of each write-back (quiet, fault, recovery)
  // Loop state.
  std::string state_after_fault, fault_reason_after_fault, state_at_end;
  bool relevitated = false;       ///< after a loop fault: reset + levitate over Modbus worked
  /// Counters named as in docs/register-map.md, read over Modbus at the end (fault window deltas).
  std::map<std::string, uint64_t> counters;
  std::string fault_counter;      ///< the counter(s) that report this fault
  uint64_t modbus_requests = 0;   ///< modbus_flood: requests the flood sent
  double command_max_ms_quiet = 0, command_max_ms_fault = 0;  ///< the operator's arm + capture command, worst round trip, ms
  uint64_t command_failures = 0;  ///< operator commands that did not get through (link error)
  double wall_s = 0;
  double loadavg = 0;             ///< 1-minute load average of the machine at the start
  std::string json() const;
};

/// Run one scenario. Throws std::runtime_error if the rig cannot start.
RigResult run_fault_rig(const RigOptions& options);

}  // namespace amb::sil::faults
