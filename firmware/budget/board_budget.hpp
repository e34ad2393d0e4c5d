#pragma once
// The board's memory and storage budget, computed from its board file: every sizeable buffer
// with its size and where the size comes from, and the event store's limits with the worst
// case per event. Configure time (allocates); the numbers are served on the supervisory link
// (registers 0x0700.., docs/register-map.md) and listed in docs/board-budget.md; amb-firmware
// prints the table when it starts (either backend).
#include <cstdint>
#include <string>
#include <vector>

namespace amb::board { struct BoardConfig; }

namespace amb::fw {

/// One buffer of the running board.
struct BufferBudget {
  std::string name;      ///< what it is, e.g. "capture ring"
  uint64_t bytes = 0;    ///< its size, bytes
  std::string basis;     ///< how the size follows from the board file (formula with the values)
  bool resident = true;  ///< true: allocated at configure, held (and locked) until stop; false: per event, in the event thread, freed after
};

/// What the budget depends on besides the board file (the service's set-up).
struct BudgetOptions {
  bool analysis_thread = true;              ///< the analysis thread runs (tracker enabled and not --no-analysis)
  uint64_t thread_stack_bytes = 512 * 1024; ///< stack of each thread the service creates, bytes
  int writer_max_pending = 4;               ///< events the event writer holds for a retry (WriterOptions::max_pending)
};

/// Threads the service creates besides its main thread: loop, Modbus server, event writer,
/// and the analysis thread when it runs.
int service_threads(const BudgetOptions& o);

/// The buffers, resident ones first, in the fixed order of the register block 0x0720.. (an
/// entry that does not apply, e.g. the tracker without the analysis thread, has 0 bytes).
std::vector<BufferBudget> buffer_budget(const board::BoardConfig& board, const BudgetOptions& o = {});
/// Sum of the resident entries, bytes.
uint64_t resident_buffer_bytes(const std::vector<BufferBudget>& table);

/// The event store's budget from the board's [capture] table.
struct StorageBudget {
  uint64_t window_samples = 0;       ///< samples per event (pre + post at the loop rate)
  uint64_t event_bytes_worst = 0;    ///< bytes of one event file at that window (diagnosis and analysis included): the largest the board writes
  uint64_t capacity_bytes = 0;       ///< [capture] storage_capacity_bytes
  uint64_t max_events = 0;           ///< [capture] max_events
  uint64_t events_kept = 0;          ///< events the store keeps at the worst case: min(max_events, capacity / event_bytes_worst)
  uint64_t wear_record_bytes = 0;    ///< the wear record on storage: two generation slots (header + AMBW v1 record)
  const char* policy = "";           ///< [capture] storage_policy
};
StorageBudget storage_budget(const board::BoardConfig& board);

}  // namespace amb::fw
