#pragma once
// Run a loop-sensitivity sweep and bring its event home, either on a board file's simulated rig
// (the firmware in the loop: levitate, start, run, store) or on a connected board over Modbus
// TCP (arm and start the sweep with the board's key, poll its progress registers, download the
// new `sweep` event, CRC-checked). Writes the event file into `out_dir` and decodes it.
// Progress lines go to `progress` (the CLI prints them on stderr). Host side, no real-time rules.
#include <cstdint>
#include <functional>
#include <string>

#include "firmware/board/board.hpp"
#include "host-tools/core/link/modbus_link.hpp"
#include "host-tools/core/sweep/sweep_record.hpp"

namespace amb::host::sweep {

struct AcquireOptions {
  std::string out_dir = "amb-out";          ///< where the event file is written (created)
  double timeout_s = 900.0;                 ///< sweep time allowed (simulated, or wall over Modbus), s
  bool spin = false;                        ///< SIL: sweep at the operating speed instead of at rest
  uint64_t noise_seed = 1;                  ///< SIL: the plant's sensor-noise seed
  double poll_s = 0.25;                     ///< Modbus: progress poll interval, s
  std::function<void(const std::string&)> progress;  ///< progress lines (may be empty)
};

struct AcquireResult {
  SweepRecord record;          ///< the decoded event
  std::string event_path;      ///< the event file written
  std::string event_name;      ///< its name on the board ("event_NNNNNNNN.ambe")
  uint64_t event_bytes = 0;
  uint32_t refusals = 0;       ///< the board's sweep refusal counter after the run
  uint32_t aborts = 0;         ///< the board's sweep abort counter after the run
};

/// Sweep failed at run time (refused, aborted before any axis, timeout, storage, link).
class AcquireError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// SIL: the board's simulated rig. Throws AcquireError.
AcquireResult acquire_sweep_sil(const board::BoardConfig& board, const AcquireOptions& o);

/// Over Modbus TCP: `arm_key` is the board's [comms.modbus] arm_key. Throws AcquireError,
/// link::LinkError, link::ModbusException.
AcquireResult acquire_sweep_modbus(const link::LinkOptions& link_options, uint32_t arm_key, const AcquireOptions& o);

}  // namespace amb::host::sweep
