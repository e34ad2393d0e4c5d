// Phase D/E: load over the circumference and the wear record update; and the drop model as
// the SIL plant under the firmware.
#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "firmware/board/board.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/core/wear/load_map.hpp"
#include "host-tools/core/wear/wear_update.hpp"
#include "model/drop/drop_model.hpp"
#include "model/drop/drop_simulation.hpp"
#include "tests/support/bath_board.hpp"

using amb::test::bath_board;

namespace md = amb::model::drop;
namespace hw = amb::host::wear;

TEST(LoadMap, BinsFollowTheBoardConvention) {
  EXPECT_EQ(hw::load_bin(0.0), 0);
  EXPECT_EQ(hw::load_bin(179.5), 179);
  EXPECT_EQ(hw::load_bin(-0.5), 359);
  EXPECT_EQ(hw::load_bin(720.2), 0);
}

TEST(WearRecord, DropEventLoadsTheBottomAndAccumulates) {
  md::DropModel m(bath_board().plant, bath_board().controller, bath_board().rate_hz, md::DropOptions{});
  m.set_friction_coefficient(0.15);
  md::DropScenario sc;
  sc.window_s = 0.3;
  const md::DropTrace tr = md::simulate_drop(m, sc, true);
  const auto load = hw::event_load(tr.contact_steps);
  for (size_t b = 0; b < 2; ++b) {
    const auto& l = load[b].load_n;
    const auto top = std::max_element(l.begin(), l.end()) - l.begin();
    EXPECT_GE(top, 150);  // a drop loads the bottom (180 deg)
    EXPECT_LE(top, 210);
    // The time-mean load is the weight share: sum(|F| h) / window ~ m g / 2 within 30 %.
    double impulse = 0.0;
    for (double v : l) impulse += v * hw::k_load_reference_period_s;
    EXPECT_NEAR(impulse / sc.window_s, 0.5 * m.rotor_mass_kg() * 9.81, 0.3 * 0.5 * m.rotor_mass_kg() * 9.81);
    EXPECT_NEAR(load[b].friction_energy_j, b == 0 ? tr.ledger.friction_dissipated_j - load[1].friction_energy_j
                                                  : tr.ledger.friction_dissipated_j - load[0].friction_energy_j,
                1e-9);
  }
  hw::WearEvent ev;
  ev.load = load;
  ev.friction_coefficient = 0.15;
  ev.rubbing[0].swing_s = 0.25;
  hw::WearOptions wo;
  amb::fw::WearRecord r0;
  r0.sequence = 41;
  const auto r1 = hw::update_wear_record(r0, ev, "bath-amb-rig", 1000, wo);
  const auto r2 = hw::update_wear_record(r1, ev, "bath-amb-rig", 2000, wo);
  EXPECT_EQ(r2.sequence, 43u);
  EXPECT_EQ(r2.event_count, 2u);
  EXPECT_NEAR(r2.bearing[0].swing_s, 0.5f, 1e-6f);
  EXPECT_NEAR(r2.bearing[0].cumulative_load_n[180], 2.0f * r2.bearing[0].event_load_n[180], 1e-3f * r2.bearing[0].event_load_n[180] + 1e-6f);
  EXPECT_NEAR(r2.bearing[0].life_used_fraction, r2.bearing[0].friction_energy_j / 20000.0f, 1e-7f);
  // The existing format round-trips (CRC) unchanged.
  amb::fw::WearRecord back;
  std::string err;
  ASSERT_TRUE(amb::fw::decode_wear_record(amb::fw::encode_wear_record(r2), back, err)) << err;
  EXPECT_EQ(back.sequence, 43u);
  EXPECT_EQ(back.life_model, hw::life_model_name(wo));
  EXPECT_THROW(hw::update_wear_record(r2, ev, "other-board", 3000, wo), std::invalid_argument);
}

TEST(DropModelSil, RunsUnderTheFirmware) {
  md::DropOptions o;
  o.internal_controller = false;
  auto plant = std::make_unique<md::DropModel>(bath_board().plant, bath_board().controller, bath_board().rate_hz, o);
  const md::DropModel* model = plant.get();
  amb::sil::SilOptions so;
  amb::sil::SilRig rig(bath_board(), std::move(plant), so);
  rig.run_for(0.05);
  EXPECT_NEAR(model->state().t_s, 0.05, 1e-3);
  // Resting on the touchdown bearings: the rotor is at the bottom of the clearance.
  EXPECT_LT(model->aux_position_m(0)[1], -0.9 * bath_board().plant.aux[0].clearance_m);
}
