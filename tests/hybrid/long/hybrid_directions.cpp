// Long validation of the hybrid model on CWRU (label long; docs/hybrid.md): both directions
// (train 1797 -> predict 1750, train 1750 -> predict 1797) for the outer and inner race, and
// three noise seeds each. Every run must keep the hybrid above both baselines.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "host-tools/core/hybrid/hybrid_model.hpp"
#include "tests/support/test_paths.hpp"

namespace hy = amb::host::hybrid;

namespace {
hy::Record rec(const char* f, hy::BearingState s, double rpm, double load) {
  hy::Record r;
  r.path = std::string(amb::test::shared_dir()) + "/data/measured/cwru/" + f + ".mat";
  r.state = s;
  r.op = {rpm, load};
  hy::load_record(r);
  return r;
}
}  // namespace

TEST(HybridCwruLong, BothDirectionsThreeSeeds) {
  using S = hy::BearingState;
  const std::vector<hy::Record> at1797 = {rec("1797_Normal", S::healthy, 1797, 0),
                                          rec("1797_IR_7_DE12", S::inner_race, 1797, 0),
                                          rec("1797_ORat6_7_DE12", S::outer_race, 1797, 0),
                                          rec("1797_B_7_DE12", S::ball, 1797, 0)};
  const std::vector<hy::Record> at1750 = {rec("1750_IR_7_DE12", S::inner_race, 1750, 2),
                                          rec("1750_ORat6_7_DE12", S::outer_race, 1750, 2)};
  nlohmann::json out = nlohmann::json::array();
  for (int dir = 0; dir < 2; ++dir) {
    const auto& train = dir == 0 ? at1797 : at1750;
    const std::vector<hy::Record> test = dir == 0 ? at1750 : std::vector<hy::Record>{at1797[1], at1797[2]};
    for (uint64_t seed : {1u, 2u, 3u}) {
      hy::TrainOptions o;
      o.seed = seed;
      const auto m = hy::train_hybrid(train, o);
      for (const auto& t : test) {
        const auto c = hy::score(hy::predict_hybrid(m, t.state, t.op), hy::measured_spectra(m, t));
        std::printf("train %s -> %-10s %.0f rpm seed %llu | log: hyb %.3f phys %.3f data %.3f | env: hyb %.3f phys %.3f "
                    "data %.3f\n",
                    dir == 0 ? "1797" : "1750", hy::state_name(t.state), t.op.speed_rpm,
                    static_cast<unsigned long long>(seed), c.log_psd_hybrid, c.log_psd_physics, c.log_psd_data_only,
                    c.env_hybrid, c.env_physics, c.env_data_only);
        out.push_back({{"train_rpm", dir == 0 ? 1797 : 1750},
                       {"state", hy::state_name(t.state)},
                       {"seed", seed},
                       {"contact_angle_deg", m.calibration.contact_angle_rad * 180 / M_PI},
                       {"log_spectrum", {c.log_psd_hybrid, c.log_psd_physics, c.log_psd_data_only}},
                       {"envelope_spectrum", {c.env_hybrid, c.env_physics, c.env_data_only}}});
        EXPECT_GT(c.log_psd_hybrid, std::max(c.log_psd_physics, c.log_psd_data_only)) << t.path << " seed " << seed;
        EXPECT_GT(c.env_hybrid, std::max(c.env_physics, c.env_data_only)) << t.path << " seed " << seed;
      }
    }
    // Ablation (docs/hybrid.md, "Kinematic transport"): the map with the transported training
    // spectrum as a second physics input on both spectra, seed 1.
    hy::TrainOptions o;
    o.transport_env = o.transport_log_psd = true;
    const auto m = hy::train_hybrid(train, o);
    for (const auto& t : test) {
      const auto p = hy::predict_hybrid(m, t.state, t.op);
      const auto c = hy::score(p, hy::measured_spectra(m, t));
      std::printf("train %s -> %-10s %.0f rpm transport on | log: hyb %.3f (8-DOF-only map %.3f, transport alone %.3f) | "
                  "env: hyb %.3f (8-DOF-only map %.3f, transport alone %.3f)\n",
                  dir == 0 ? "1797" : "1750", hy::state_name(t.state), t.op.speed_rpm, c.log_psd_hybrid,
                  c.log_psd_hybrid_sim, c.log_psd_transport, c.env_hybrid, c.env_hybrid_sim, c.env_transport);
      out.push_back({{"train_rpm", dir == 0 ? 1797 : 1750},
                     {"state", hy::state_name(t.state)},
                     {"variant", "transport_on"},
                     {"reference", p.reference},
                     {"log_spectrum", {c.log_psd_hybrid, c.log_psd_hybrid_sim, c.log_psd_transport}},
                     {"envelope_spectrum", {c.env_hybrid, c.env_hybrid_sim, c.env_transport}}});
      // The reference is the training record of the same state; the transported envelope
      // places the lines at the new speed (data only, unmoved, stays near 0.1).
      EXPECT_EQ(p.reference.rfind(hy::state_name(t.state), 0), 0u) << p.reference;
      EXPECT_GT(c.env_transport, 0.5) << t.path;
    }
  }
  std::filesystem::create_directories(amb::test::artefact_dir());
  std::ofstream(std::string(amb::test::artefact_dir()) + "/hybrid_cwru_directions.json") << out.dump(2) << '\n';
}
