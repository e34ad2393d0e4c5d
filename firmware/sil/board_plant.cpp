#include "firmware/sil/sil_rig.hpp"
#include "model/plant/rotor_amb_plant.hpp"

namespace amb::sil {

std::unique_ptr<model::Plant> make_board_plant(const board::BoardConfig& board, uint64_t noise_seed) {
  model::RotorAmbPlant::Options o;
  o.noise_seed = noise_seed;
  return std::make_unique<model::RotorAmbPlant>(board.plant, o);
}

}  // namespace amb::sil
