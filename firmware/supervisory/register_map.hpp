#pragma once
// The supervisory register map (addresses: register_addresses.hpp, description:
// docs/register-map.md) as a hal::RegisterHandler. Called only from the supervisory server's
// thread (never from the loop): it reads the loop's status through lock-free snapshots,
// posts commands through Supervisor::post, serves the event list and the event download
// window from hal::Storage, and takes wear-record write-backs, validated by WearStore before
// they replace the stored record. Unknown addresses and writes to read-only registers are
// answered with exception 2, bad values with 3, unsafe writes while levitated with 6.
// Write access: every command register (command, event delete, wear-record commit) needs the
// arm sequence (key from the board file, one operation, single use, short window): exception 1
// without it; and it is refused with exception 6 in a lifecycle state where the command does
// not apply. Every refusal is counted (AccessCounters).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "firmware/analysis/analysis_task.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/budget/board_budget.hpp"
#include "firmware/budget/runtime_budget.hpp"
#include "firmware/events/event_store.hpp"
#include "firmware/fieldbus/field_bus_front_end.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_addresses.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

/// Counters of the Modbus transport, provided by the server backend.
struct LinkCounters {
  uint64_t requests = 0, exceptions = 0, bad_frames = 0, wrong_unit = 0, connections = 0;
  uint64_t refused_connections = 0;  ///< connections closed at once: max_clients reached
};

/// Counters of the write access (registers 0x0520.., 0x0530..).
struct AccessCounters {
  uint64_t arms = 0;               ///< arm writes accepted
  uint64_t arm_key_mismatch = 0;   ///< arm writes with a wrong key (exception 3)
  uint64_t commands = 0;           ///< command writes accepted
  uint64_t refused_not_armed = 0;  ///< command writes without a matching, unexpired arm (exception 1)
  uint64_t refused_state = 0;      ///< command writes in a lifecycle state where they do not apply (exception 6)
  uint64_t refused_value = 0;      ///< writes refused for a bad value or length (exception 3)
  uint64_t illegal_address = 0;    ///< reads or writes of addresses outside the map / read-only (exception 2)
};

/// Where the register map gets its data. Every member is optional (absent: reads as 0).
/// The functions are called from the server thread and must be thread-safe.
/// Sweep events in the store (the event writer's count).
struct SweepStoreInfo {
  uint64_t stored = 0;        ///< sweep events stored
  uint64_t last_number = 0;   ///< number of the newest (0: none)
};

struct RegisterSources {
  Supervisor* supervisor = nullptr;                       ///< status snapshots, command posting
  std::function<LoopStats()> loop_stats;                  ///< published loop statistics
  std::function<hal::CanStats()> can_stats;
  std::function<fieldbus::FieldBusCounters()> fieldbus;
  std::function<LinkCounters()> link;
  std::function<bool()> nodes_alive;                      ///< field-bus nodes heard within the timeout
  std::function<AnalysisStatus()> analysis;               ///< analysis task results (absent: tracker not running)
  std::function<StoreCounters()> storage;                 ///< event-store counters (the event writer's)
  std::function<RuntimeBudget()> runtime_budget;          ///< measured memory, CPU shares, start-up time (absent: not measured)
  std::vector<uint64_t> buffer_bytes;                     ///< fw::buffer_budget sizes, bytes, in its order (at most regs::k_max_buffer_entries)
  StorageBudget storage_budget;                           ///< fw::storage_budget of the board
  std::function<SweepStoreInfo()> sweep_store;            ///< sweep events stored (absent: 0)
  std::function<bool()> manual_capture;                   ///< request a manual capture trigger (absent: command 6 refused, exception 4)
  /// Time for the arm window, ns, any monotonic clock that may be read from the server thread
  /// (the linux backend passes CLOCK_MONOTONIC). Absent: std::chrono::steady_clock.
  std::function<int64_t()> now_ns;
  uint32_t arm_key = 0;                                   ///< [comms.modbus] arm_key; 0: commands refused (exception 1)
  int64_t arm_window_ns = 5'000'000'000;                  ///< [comms.modbus] arm_window_ms, ns
  uint8_t speed_source = 0;                               ///< fw::SpeedSource of the board
  hal::Storage* events = nullptr;                         ///< event files (opaque blobs), listed sorted
  WearStore* wear = nullptr;                              ///< opened wear-record store
  int wear_corrupt_at_start = 0;                          ///< from WearStore::open()
  std::string board_name;
  uint16_t unit_id = 1;
  double rate_hz = 0.0;                                   ///< control loop rate, Hz
};

class RegisterMap final : public hal::RegisterHandler {
 public:
  explicit RegisterMap(RegisterSources sources);

  Status read_registers(uint16_t address, std::span<uint16_t> out) override;
  Status write_registers(uint16_t address, std::span<const uint16_t> values) override;

  /// Counters (server thread, or any thread once the server has stopped).
  uint64_t refused_unsafe() const { return access_.refused_state; }
  uint64_t illegal_addresses() const { return access_.illegal_address; }
  const AccessCounters& access_counters() const { return access_; }
  uint64_t wear_store_failures() const { return wear_store_failures_; }
  WriteBackResult last_writeback() const { return wb_result_; }

 private:
  struct EventEntry {
    std::string name;
    uint32_t size = 0;
    uint32_t crc = 0;
  };
  using Block = std::vector<uint16_t>;

  bool unsafe_now() const;
  int64_t now_ns() const;
  /// Consume the arm (single use): true if it names `op` and has not expired.
  bool take_arm(uint16_t op);
  /// Whether the lifecycle state allows `op` now (status snapshot of the loop).
  bool state_allows(uint16_t op) const;
  Status refuse_value();
  Status write_arm(std::span<const uint16_t> v);
  void refresh_events();
  bool render(uint16_t start, uint16_t end, Block& b);
  Status write_command(std::span<const uint16_t> v);
  Status write_sweep_command(uint16_t op);
  Status write_delete(std::span<const uint16_t> v);
  Status write_select(std::span<const uint16_t> v);
  Status write_wb_control(std::span<const uint16_t> v);
  Status write_wb_chunk(std::span<const uint16_t> v);

  RegisterSources src_;
  // Event directory (cached; an event file's content is assumed immutable once named, and
  // re-checked against its CRC whenever it is loaded for download).
  std::vector<EventEntry> events_;
  std::vector<std::string> event_names_;
  uint16_t list_version_ = 0;
  uint16_t browse_index_ = 0;
  // Download window.
  bool dl_selected_ = false;
  uint16_t dl_status_ = regs::dl_no_selection;
  uint32_t dl_block_ = 0;
  std::string dl_name_;
  uint32_t dl_crc_ = 0;
  std::vector<uint8_t> dl_bytes_;
  // Write-back session.
  uint16_t wb_session_ = regs::wb_idle;
  uint32_t wb_size_ = 0, wb_crc_ = 0, wb_received_ = 0;
  std::vector<uint8_t> wb_staging_;
  WriteBackResult wb_result_ = WriteBackResult::none;
  uint16_t command_result_ = 0;
  // Arm: the operation armed (0 none) and when, ns of now_ns().
  uint16_t armed_op_ = 0;
  int64_t armed_at_ns_ = 0;
  AccessCounters access_{};
  uint64_t wear_store_failures_ = 0;
};

}  // namespace amb::fw
