#pragma once
// Event download and wear-record write-back over the supervisory register map, on top of a
// ModbusLink (which reconnects and retries). Downloads resume from a partial file (and after
// dropped connections); every block is checked by its CRC-32C and the whole item by the CRC-32C
// listed by the board. Write-backs resume the board's session and are verified by the board.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host-tools/core/link/modbus_link.hpp"

namespace amb::host::link {

struct BoardIdentity {
  uint16_t map_version = 0;
  uint16_t firmware_version = 0;
  std::string board_name;
  uint16_t loop_rate_hz = 0;
  uint16_t wear_record_bytes = 0;
  uint16_t block_bytes = 0;
  uint16_t chunk_bytes = 0;
  uint16_t state = 0;        ///< fw::State
  uint16_t fault = 0;        ///< fw::FaultReason
  uint16_t state_flags = 0;  ///< bit0 levitated (unsafe writes refused)
};

struct EventInfo {
  uint16_t index = 0;
  std::string name;
  uint32_t size = 0;    ///< bytes
  uint32_t crc32 = 0;   ///< CRC-32C of the whole file
};

struct WearSummary {
  bool present = false;
  uint32_t sequence = 0;
  uint32_t event_count = 0;
  uint32_t crc32 = 0;      ///< CRC-32C of the encoded record
  uint32_t generation = 0; ///< persistence generation on the board
  uint16_t corrupt_at_start = 0;
};

struct TransferStats {
  uint64_t bytes = 0;          ///< payload bytes moved in this run
  uint64_t resumed_from = 0;   ///< bytes already present when this run started
  double wall_s = 0.0;
  int reconnects = 0;
  uint64_t requests = 0;
  uint64_t block_crc_errors = 0;
};

BoardIdentity read_identity(ModbusLink& link);
std::vector<EventInfo> list_events(ModbusLink& link);
WearSummary read_wear_summary(ModbusLink& link);

/// Download item `index` (or regs::k_wear_item_index) whose CRC-32C is `crc32` and size `size`.
/// `data` holds bytes already downloaded (resume point, rounded down to a block); it is
/// extended in place. `checkpoint` (optional) is called with the data after every block so a
/// caller can persist progress. Throws LinkError / std::runtime_error (item changed, CRC).
void download(ModbusLink& link, uint16_t index, uint32_t crc32, uint32_t size, std::vector<uint8_t>& data,
              TransferStats& stats, const std::function<void(const std::vector<uint8_t>&)>& checkpoint = {});

struct WriteBackOutcome {
  uint16_t result = 0;        ///< fw::WriteBackResult code from the board
  int commit_attempts = 0;    ///< armed commits sent
  std::string result_name;    ///< to_string(result), or "already_stored" (board holds these exact bytes)
  bool already_stored = false;
  uint32_t stored_sequence = 0;
  TransferStats stats;
};

/// Arm one operation (regs::ArmOperation) with the board's key ([comms.modbus] arm_key): the
/// next command write must follow within the board's arm window. Throws ModbusException
/// (3: wrong key, 1: the board takes no commands).
void arm(ModbusLink& link, uint32_t arm_key, uint16_t operation);
/// Arm and write the command register (1 levitate .. 5 emergency stop, 6 manual capture).
/// Throws ModbusException (1 not armed, 6 wrong lifecycle state or a command still pending).
void send_command(ModbusLink& link, uint32_t arm_key, uint16_t command);

/// Send an encoded AMBW record; resumes a session the board already holds for the same bytes.
/// The commit is armed with `arm_key`; a commit whose arm was lost (expired, or taken by another
/// client) or that failed in the board's storage is armed and committed again (3 attempts).
/// Returns the board's verdict (accepted or why not); throws on link failure.
WriteBackOutcome write_back(ModbusLink& link, const std::vector<uint8_t>& record, uint32_t arm_key);

/// File helpers for resumable downloads: `<dir>/<name>` when complete, `<dir>/.<name>.<crc>.part` meanwhile.
std::string part_path(const std::string& dir, const EventInfo& e);

}  // namespace amb::host::link
