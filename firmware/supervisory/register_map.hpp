#pragma once
// The supervisory register map (addresses: register_addresses.hpp, description:
// docs/register-map.md) as a hal::RegisterHandler. Called only from the supervisory server's
// thread (never from the loop): it reads the loop's status through lock-free snapshots,
// posts commands through Supervisor::post, serves the event list and the event download
// window from hal::Storage, and takes wear-record write-backs, validated by WearStore before
// they replace the stored record. Unknown addresses and writes to read-only registers are
// answered with exception 2, bad values with 3, unsafe writes while levitated with 6.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "firmware/analysis/analysis_task.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/supervisor.hpp"
#include "firmware/fieldbus/field_bus_front_end.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_addresses.hpp"
#include "hal/interfaces.hpp"

namespace amb::fw {

/// Counters of the Modbus transport, provided by the server backend.
struct LinkCounters {
  uint64_t requests = 0, exceptions = 0, bad_frames = 0, wrong_unit = 0, connections = 0;
};

/// Where the register map gets its data. Every member is optional (absent: reads as 0).
/// The functions are called from the server thread and must be thread-safe.
struct RegisterSources {
  Supervisor* supervisor = nullptr;                       ///< status snapshots, command posting
  std::function<LoopStats()> loop_stats;                  ///< published loop statistics
  std::function<hal::CanStats()> can_stats;
  std::function<fieldbus::FieldBusCounters()> fieldbus;
  std::function<LinkCounters()> link;
  std::function<bool()> nodes_alive;                      ///< field-bus nodes heard within the timeout
  std::function<AnalysisStatus()> analysis;               ///< analysis task results (absent: tracker not running)
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

  /// Requests refused because the rotor was levitated (any thread may not call; server thread).
  uint64_t refused_unsafe() const { return refused_unsafe_; }
  uint64_t illegal_addresses() const { return illegal_address_; }
  WriteBackResult last_writeback() const { return wb_result_; }

 private:
  struct EventEntry {
    std::string name;
    uint32_t size = 0;
    uint32_t crc = 0;
  };
  using Block = std::vector<uint16_t>;

  bool unsafe_now() const;
  void refresh_events();
  bool render(uint16_t start, uint16_t end, Block& b);
  Status write_command(std::span<const uint16_t> v);
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
  uint64_t refused_unsafe_ = 0, illegal_address_ = 0;
};

}  // namespace amb::fw
