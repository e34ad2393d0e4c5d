// model::StepRows (model/rig/step_rows.hpp): the one fixed-capacity copy of a rig reduction that
// the SIL plant and the drop model step on. The rig's rows must arrive bit for bit; the
// unbalance, the AMB laws and the sensor and actuator directions must be the caller's own
// (they may differ from the parameters the rig model was built from); a reduction above the
// capacity must be refused with the caller named.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "model/amb/amb_force.hpp"
#include "model/rig/rig_model.hpp"
#include "model/rig/step_rows.hpp"
#include "tests/plant/rig_fixture.hpp"

namespace amb::model {
namespace {

bool same_bits(const StepModeVec& a, const Eigen::RowVectorXd& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (a(i) != b(i)) return false;
  return true;
}

TEST(StepRows, CopiesTheRigRowsAndTakesTheCallersUnbalanceLawsAndDirections) {
  const auto board = test::board_from_repo("bath-amb-rig");
  const RigModel rig(board.plant);
  // The caller's parameters: same rotor and planes, other unbalance, sensor and actuator angles and AMB law.
  PlantParams own = board.plant;
  ASSERT_FALSE(own.rotor.disks.empty());
  for (auto& d : own.rotor.disks) {
    d.unbalance_kg_m += 2e-4;
    d.unbalance_phase_deg += 40.0;
  }
  for (auto& s : own.sensor) s.angle_deg += 10.0;
  own.amb[1].actuator_angle_deg[0] += 5.0;
  own.amb[0].ks_n_per_m *= 1.1;  // a stiffer negative stiffness: a larger bias in the law (ks / ki = i0 / g0)
  ASSERT_TRUE(rig.differs_from(own).empty()) << "the test must vary only what a user may vary";

  const RigReduction& red = rig.board_reduction();
  const StepRows s = make_step_rows(rig, red, own, "test");
  ASSERT_EQ(s.modes, red.modes());
  EXPECT_EQ(s.spin_inertia_kg_m2, rig.rotor().polar_inertia_kg_m2);
  EXPECT_TRUE(same_bits(s.w2, red.reduced.omega2.transpose()));
  EXPECT_TRUE(same_bits(s.damp, red.reduced.damping.transpose()));
  EXPECT_TRUE(same_bits(s.gravity_y, red.gravity_y_n.transpose()));
  EXPECT_TRUE((s.polar.array() == red.reduced.polar.array()).all());
  EXPECT_TRUE(same_bits(s.coupling, red.coupling));
  for (size_t b = 0; b < 2; ++b) {
    EXPECT_TRUE(same_bits(s.amb[b], red.amb[b])) << b;
    EXPECT_TRUE(same_bits(s.aux[b], red.aux[b])) << b;
    EXPECT_EQ(s.law[b].bias_a, magnet::make_axis_law(own.amb[b]).bias_a) << b;
    for (size_t a = 0; a < 2; ++a)
      EXPECT_EQ(s.act_dir[2 * b + a], magnet::axis_direction(own.amb[b].actuator_angle_deg[a])) << b << a;
  }
  EXPECT_NE(s.law[0].bias_a, magnet::make_axis_law(board.plant.amb[0]).bias_a);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_TRUE(same_bits(s.sensor[k], red.sensor[k])) << k;
    EXPECT_EQ(s.sensor_dir[k], magnet::axis_direction(own.sensor[k].angle_deg)) << k;
    EXPECT_NE(s.sensor_dir[k], magnet::axis_direction(board.plant.sensor[k].angle_deg)) << k;
  }
  const UnbalanceExpansion mine = unbalance_expansion(red, own.rotor);
  const UnbalanceExpansion rigs = unbalance_expansion(red, board.plant.rotor);
  EXPECT_TRUE(same_bits(s.unb_sin, mine.sin_sum.transpose()));
  EXPECT_TRUE(same_bits(s.unb_cos, mine.cos_sum.transpose()));
  EXPECT_FALSE(same_bits(s.unb_sin, rigs.sin_sum.transpose()));
  EXPECT_TRUE(same_bits(s.mid_disk, mine.mid_row));
  EXPECT_EQ(s.mid_disk_phase_rad, mine.mid_phase_rad);
}

TEST(StepRows, AReductionAboveTheCapacityIsRefusedNamingTheCaller) {
  const auto board = test::board_from_repo("bath-amb-rig");
  const RigModel rig(board.plant);
  const RigReduction all = rig.reduction(0);  // every mode of the basis
  ASSERT_GT(all.modes(), k_step_max_modes) << "the Bath rotor's full basis must exceed the capacity for this test";
  try {
    (void)make_step_rows(rig, all, board.plant, "drop model");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("drop model: modes per plane (" + std::to_string(all.modes()) + ")", 0), 0u) << e.what();
  }
  EXPECT_NO_THROW((void)make_step_rows(rig, rig.reduction(k_step_max_modes), board.plant, "drop model"));
}

}  // namespace
}  // namespace amb::model
