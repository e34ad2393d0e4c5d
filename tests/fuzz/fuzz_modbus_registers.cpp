// Modbus requests come from any client that reaches the port. The input is read as a
// sequence of requests (function byte, start address, count, values) applied to the board's
// register map exactly as the TCP server applies them: reads of 1..125 registers, writes of
// 1..123 registers (the Modbus PDU limits). The map must answer every request with a value or
// a Modbus exception, never crash, and a refused write must not change what reads back.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/sim/sim_rig.hpp"
#include "tests/firmware/register_stores.hpp"

namespace {

// The board and a supervisor configured on it once (configure() assembles the rotor model:
// most of an execution's time when done per input); each input starts from reset(), the
// state configure() leaves, so every input runs from the same state.
struct Board {
  amb::board::BoardConfig board = amb::board::load_board("bath-amb-rig");
  amb::fw::Supervisor sup;
  Board() { sup.configure(board); }
};
Board& shared_board() {
  static Board b;
  return b;
}

}  // namespace

// The one-time set-up (the rotor model and the sweep's multisine table, several seconds under
// the fuzzer's instrumentation on a loaded machine) before any input, so that it does not
// count against the first input's time limit.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)shared_board();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& board = shared_board().board;
  amb::fw::Supervisor& sup = shared_board().sup;
  sup.reset();
  amb::test::MemoryStores stores(board.name);
  std::string error;
  const std::vector<uint8_t> blob(300, 0xA5);  // an opaque event file to list and download
  stores.events.write_atomic("event_0001.ambe", blob, error);
  stores.wear.open();
  amb::fw::RegisterMap map(amb::test::board_sources(sup, stores, board));

  std::vector<uint16_t> regs(125), values(123);
  size_t i = 0;
  while (i + 4 <= size) {
    const uint8_t fc = data[i];
    const uint16_t address = static_cast<uint16_t>((data[i + 1] << 8) | data[i + 2]);
    i += 3;
    if (fc & 1u) {  // write multiple registers
      const size_t n = 1 + data[i++] % 123;
      size_t k = 0;
      for (; k < n && i + 2 <= size; ++k, i += 2) values[k] = static_cast<uint16_t>((data[i] << 8) | data[i + 1]);
      if (k == 0) break;
      map.write_registers(address, std::span<const uint16_t>(values.data(), k));
    } else {  // read holding registers
      const size_t n = 1 + data[i++] % 125;
      const auto st = map.read_registers(address, std::span<uint16_t>(regs.data(), n));
      if (st > amb::hal::RegisterHandler::busy) __builtin_trap();
    }
  }
  return 0;
}
