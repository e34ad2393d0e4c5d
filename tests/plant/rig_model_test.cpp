// model::RigModel (issue 37): one rig structure built once, shared by every model of the rig.
// The reductions it cuts from its modal basis must be bit-identical to a reduction solved for
// that count directly (the figures of every user stay bit-identical), a plant on a shared rig
// model must step exactly as one that builds its own, and parameters of another rotor must be
// refused with the difference named.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "model/drop/drop_model.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "model/rig/rig_model.hpp"
#include "model/rotor/modal_reduction.hpp"
#include "tests/plant/rig_fixture.hpp"

namespace amb::model {
namespace {

bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

class RigModelBoards : public ::testing::TestWithParam<std::string> {};

TEST_P(RigModelBoards, ReductionsAreBitIdenticalToADirectSolve) {
  const auto board = test::board_from_repo(GetParam());
  const RigModel rig(board.plant);
  const rotor::RotorModel fe = rotor::build_rotor_model(board.plant.rotor);
  for (int k : {2, 3, board.plant.rotor.modes_kept, 0}) {
    const rotor::ReducedRotor direct = rotor::reduce_rotor(fe, board.plant.rotor, k);
    const RigReduction r = rig.reduction(k);
    ASSERT_EQ(r.modes(), direct.modes) << k;
    EXPECT_TRUE(same_bits(r.reduced.shapes, direct.shapes)) << k;
    EXPECT_TRUE(same_bits(r.reduced.omega2, direct.omega2)) << k;
    EXPECT_TRUE(same_bits(r.reduced.damping, direct.damping)) << k;
    EXPECT_TRUE(same_bits(r.reduced.polar, direct.polar)) << k;
    EXPECT_TRUE(same_bits(r.gravity_y_n, rotor::modal_gravity_load(fe, direct, board.plant.gravity_m_s2))) << k;
    for (size_t s = 0; s < 4; ++s)
      EXPECT_TRUE(same_bits(r.sensor[s], rotor::modal_interpolation(fe, direct, board.plant.sensor[s].axial_m))) << k;
    for (size_t b = 0; b < 2; ++b) {
      EXPECT_TRUE(same_bits(r.aux[b], rotor::modal_interpolation(fe, direct, board.plant.aux[b].axial_m))) << k;
      EXPECT_TRUE(same_bits(r.amb[b], rotor::modal_interpolation(fe, direct, board.plant.amb[b].axial_m))) << k;
    }
  }
  EXPECT_EQ(rig.board_reduction().modes(), rig.reduction(board.plant.rotor.modes_kept).modes());
}

TEST_P(RigModelBoards, APlantOnASharedRigModelStepsExactlyAsOneThatBuildsItsOwn) {
  const auto board = test::board_from_repo(GetParam());
  const auto rig = RigModel::make(board.plant);
  RotorAmbPlant own(board.plant, RotorAmbPlant::Options{});
  RotorAmbPlant shared(rig, board.plant, RotorAmbPlant::Options{});
  own.reset(false, 0.0);
  shared.reset(false, 0.0);
  PlantInputs in{};
  for (int i = 0; i < 200; ++i) {
    in.amplifiers_enabled = true;
    in.current_demand_a = {0.3 * std::sin(0.01 * i), -0.2, 0.1, 0.05 * i / 200.0};
    own.step(1e-4, in);
    shared.step(1e-4, in);
  }
  for (size_t s = 0; s < 4; ++s) EXPECT_EQ(own.outputs().displacement_m[s], shared.outputs().displacement_m[s]) << s;
  // The plant varies what is its own (an offset) on the same shared structure.
  PlantParams shifted = board.plant;
  shifted.aux[0].centre_offset_y_m += 50e-6;
  EXPECT_NO_THROW(RotorAmbPlant(rig, shifted, RotorAmbPlant::Options{}));
}

INSTANTIATE_TEST_SUITE_P(Boards, RigModelBoards, ::testing::Values("bath-amb-rig", "unicamp-amb-rig"));

TEST(RigModel, ParametersOfAnotherRotorAreRefusedWithTheDifferenceNamed) {
  const auto bath = test::board_from_repo("bath-amb-rig");
  const auto unicamp = test::board_from_repo("unicamp-amb-rig");
  const auto rig = RigModel::make(bath.plant);
  EXPECT_TRUE(rig->differs_from(bath.plant).empty());
  EXPECT_FALSE(rig->differs_from(unicamp.plant).empty());
  PlantParams moved = bath.plant;
  moved.aux[1].axial_m += 0.01;
  EXPECT_NE(rig->differs_from(moved).find("aux bearing 1 axial_m"), std::string::npos) << rig->differs_from(moved);
  try {
    RotorAmbPlant p(rig, moved, RotorAmbPlant::Options{});
    FAIL() << "a plant on another rig's model was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("another rotor"), std::string::npos) << e.what();
  }
  PlantParams stiffer = bath.plant;
  stiffer.rotor.elements[0].youngs_modulus_pa *= 1.1;
  EXPECT_NE(rig->differs_from(stiffer).find("youngs_modulus_pa"), std::string::npos);
}

TEST(RigModel, BuildsTheRotorOnceForManyModels) {
  const auto board = test::board_from_repo("bath-amb-rig");
  const auto c0 = rotor::build_counts();
  const auto rig = RigModel::make(board.plant);
  drop::DropOptions o;
  o.internal_controller = true;
  for (int k : {0, 2}) {
    o.modes_per_plane = k;
    drop::DropModel m(rig, board.plant, board.controller, board.rate_hz, o);
    EXPECT_EQ(m.modes_per_plane(), k == 0 ? board.plant.rotor.modes_kept : 2);
  }
  RotorAmbPlant p(rig, board.plant, RotorAmbPlant::Options{});
  const auto c1 = rotor::build_counts();
  EXPECT_EQ(c1.fe_builds - c0.fe_builds, 1);
  EXPECT_EQ(c1.eigen_solves - c0.eigen_solves, 1);
}

}  // namespace
}  // namespace amb::model
