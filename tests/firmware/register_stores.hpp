#pragma once
// What a register map serves in the register tests (tests/firmware/write_access_test,
// tests/linux/register_map_test, tests/fuzz/fuzz_modbus_registers): a supervisor on a board
// and the board's event and wear-record stores in memory.
#include <string>

#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/sim/sim_rig.hpp"

namespace amb::test {

/// A board's event store and wear-record store, in memory (1 MiB each). The wear store is not
/// opened: the caller writes what it needs first, then calls wear.open().
struct MemoryStores {
  hal::sim::MemoryStorage events{1 << 20};
  hal::sim::MemoryStorage wear_storage{1 << 20};
  fw::WearStore wear;
  explicit MemoryStores(const std::string& board_name) : wear(wear_storage, board_name) {}
};

/// The sources of a register map over `sup`, the stores `s` and the board `b` (its name and
/// loop rate). The caller adds the rest (arm key, clocks, link counters).
inline fw::RegisterSources board_sources(fw::Supervisor& sup, MemoryStores& s, const board::BoardConfig& b) {
  fw::RegisterSources src;
  src.supervisor = &sup;
  src.events = &s.events;
  src.wear = &s.wear;
  src.board_name = b.name;
  src.rate_hz = b.rate_hz;
  return src;
}

}  // namespace amb::test
