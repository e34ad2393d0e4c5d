// Leave-one-operating-point-out on the nine CWRU fault records, label long (docs/hybrid.md):
//  - other seeds (the simulated sensor noise and the ensemble's bootstrap): the hybrid stays
//    above every baseline at 1750 rpm and in the log spectrum everywhere;
//  - the ablation without the 8-DOF simulation's features (the correction from the measured
//    spectra and the kinematic law only): its figures, printed for the docs.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "host-tools/core/hybrid/leave_one_out.hpp"
#include "tests/hybrid/cwru_nine.hpp"
#include "tests/support/test_paths.hpp"

namespace hy = amb::host::hybrid;
using amb::test::hybrid::k_models;

namespace {

void print(const char* what, const hy::LooResult& res) {
  std::printf("%s\n", what);
  for (const auto& r : res.rows) {
    std::printf("  %4.0f %-10s log", r.held_out.speed_rpm, hy::state_name(r.state));
    for (const char* m : k_models) std::printf(" %.3f", r.model(m).log_pearson);
    std::printf(" | env");
    for (const char* m : k_models) std::printf(" %.3f", r.model(m).env_pearson);
    std::printf("\n");
  }
}

void write(const std::string& name, const hy::LooResult& res) {
  const std::string dir = amb::test::artefact_dir();
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/" + name) << hy::loo_json(res).dump(2) << '\n';
}

}  // namespace

TEST(HybridLeaveOneOutLong, OtherSeedsKeepTheFindings) {
  const auto recs = amb::test::hybrid::cwru_nine_records();
  for (uint64_t seed : {2u, 3u}) {
    hy::TrainOptions o;
    o.threads = 2;
    o.seed = seed;
    const auto res = hy::leave_one_point_out(recs, o);
    print(("seed " + std::to_string(seed)).c_str(), res);
    write("hybrid_leave_one_out_seed" + std::to_string(seed) + ".json", res);
    for (const auto& r : res.rows) {
      SCOPED_TRACE(std::to_string(seed) + ": " + std::to_string(r.held_out.speed_rpm) + " " + hy::state_name(r.state));
      const auto& h = r.model("hybrid");
      for (const char* m : k_models) {
        if (std::string(m) == "hybrid") continue;
        EXPECT_GT(h.log_pearson, r.model(m).log_pearson) << m;
        if (r.held_out.speed_rpm == 1750) {
          EXPECT_GT(h.env_pearson, r.model(m).env_pearson) << m;
        }
      }
    }
  }
}

TEST(HybridLeaveOneOutLong, WithoutTheSimulationFeatures) {
  hy::TrainOptions o;
  o.threads = 2;
  o.correction_sim_features = false;
  const auto res = hy::leave_one_point_out(amb::test::hybrid::cwru_nine_records(), o);
  print("correction without the 8-DOF simulation's features", res);
  write("hybrid_leave_one_out_no_sim.json", res);
  for (const auto& r : res.rows) {
    EXPECT_EQ(r.chosen_log.find("sim_"), std::string::npos) << r.chosen_log;
    EXPECT_EQ(r.chosen_env.find("sim_"), std::string::npos) << r.chosen_env;
  }
}
