#pragma once
// The Bath rig's board (boards/bath-amb-rig.toml, embedded), loaded once per test process and
// shared read-only by the tests that simulate or fit on it.
#include "firmware/board/board.hpp"

namespace amb::test {

inline const amb::board::BoardConfig& bath_board() {
  static const auto b = amb::board::load_board("bath-amb-rig");
  return b;
}

}  // namespace amb::test
