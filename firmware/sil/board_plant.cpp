#include "firmware/sil/sil_rig.hpp"
#include "model/journal/journal_rig.hpp"
#include "model/plant/rotor_amb_plant.hpp"

namespace amb::sil {

std::unique_ptr<model::Plant> make_board_plant(const board::BoardConfig& board, uint64_t noise_seed) {
  model::RotorAmbPlant::Options o;
  o.noise_seed = noise_seed;
  return make_board_plant(board, o);
}

std::unique_ptr<model::Plant> make_board_plant(const board::BoardConfig& board, const model::RotorAmbPlant::Options& o) {
  auto plant = std::make_unique<model::RotorAmbPlant>(board.plant, o);
  // Optional journal bearing: placed by the AMBs and linearised at the operating speed
  // (the film force then scales with speed; see model/journal/journal_rig.hpp).
  if (board.journal.present)
    plant->set_journal(model::journal::place_journal(board.plant, board.journal,
                                                     2.0 * M_PI * board.lifecycle.operating_speed_hz));
  return plant;
}

}  // namespace amb::sil
