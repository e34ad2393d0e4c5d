#pragma once
// Shared set-up of the drop tests: the Bath rig board and a drop model on it.
#include <memory>

#include "firmware/board/board.hpp"
#include "model/drop/drop_model.hpp"
#include "model/drop/drop_simulation.hpp"

namespace amb::test {

inline const board::BoardConfig& bath_board() {
  static const board::BoardConfig b = board::load_board("bath-amb-rig");
  return b;
}

inline std::unique_ptr<model::drop::DropModel> make_drop_model(const model::PlantParams& p,
                                                               const model::drop::DropOptions& o = {}) {
  const auto& b = bath_board();
  return std::make_unique<model::drop::DropModel>(p, b.controller, b.rate_hz, o);
}

}  // namespace amb::test
