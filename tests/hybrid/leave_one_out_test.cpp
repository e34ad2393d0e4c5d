// Leave-one-operating-point-out on the nine CWRU fault records (issue 34): inner race, outer
// race and ball at 1797 rpm / 0 hp, 1750 rpm / 2 hp and 1730 rpm / 3 hp. Train on two points,
// predict the third; every model's Pearson and MSE per state and spectrum.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "host-tools/core/hybrid/leave_one_out.hpp"
#include "tests/hybrid/cwru_nine.hpp"
#include "tests/support/test_paths.hpp"

namespace hy = amb::host::hybrid;

namespace {

using amb::test::hybrid::k_models;
std::vector<hy::Record> nine_records() { return amb::test::hybrid::cwru_nine_records(); }

}  // namespace

TEST(HybridLeaveOneOut, CwruThreeOperatingPoints) {
  hy::TrainOptions o;
  o.threads = 2;
  const auto res = hy::leave_one_point_out(nine_records(), o, [](const std::string& s) { std::fprintf(stderr, "%s\n", s.c_str()); });
  ASSERT_EQ(res.rows.size(), 9u);
  std::printf("held-out  state       | log Pearson: phys  data  near  interp hybrid | env Pearson: phys  data  near  interp hybrid\n");
  for (const auto& r : res.rows) {
    std::printf("%6.0f   %-11s |", r.held_out.speed_rpm, hy::state_name(r.state));
    for (const char* m : k_models) std::printf(" %5.3f", r.model(m).log_pearson);
    std::printf(" |");
    for (const char* m : k_models) std::printf(" %5.3f", r.model(m).env_pearson);
    std::printf("\n        MSE          |");
    for (const char* m : k_models) std::printf(" %5.3f", r.model(m).log_mse);
    std::printf(" |");
    for (const char* m : k_models) std::printf(" %.2e", r.model(m).env_mse);
    std::printf("\n        band coverage log %.2f env %.2f, width log %.3f env %.2f; chosen: log [%s] env [%s]\n",
                r.band_coverage_log, r.band_coverage_env, r.band_width_log, r.band_width_env_rel, r.chosen_log.c_str(),
                r.chosen_env.c_str());
    std::printf("        inner CV: log %.3f (transport %.3f), env %.3f (transport %.3f)\n", r.cv_log, r.cv_log_baseline, r.cv_env,
                r.cv_env_baseline);
  }
  // Every prediction is the learned correction of the transported spectra (two training points
  // per state in every fold).
  double cover_log = 0, cover_env = 0;
  for (const auto& r : res.rows) {
    SCOPED_TRACE(std::to_string(r.held_out.speed_rpm) + " rpm " + hy::state_name(r.state));
    EXPECT_EQ(r.hybrid_kind, "correction");
    const auto& h = r.model("hybrid");
    for (const char* m : k_models) {
      if (std::string(m) == "hybrid") continue;
      const auto& b = r.model(m);
      ASSERT_TRUE(b.available) << m;
      // Log spectrum: the hybrid above every baseline at every held-out point (Pearson and MSE).
      EXPECT_GT(h.log_pearson, b.log_pearson) << m;
      EXPECT_LT(h.log_mse, b.log_mse) << m;
      if (r.held_out.speed_rpm == 1750) {
        // Interpolation (1750 rpm): above every baseline in the envelope too.
        EXPECT_GT(h.env_pearson, b.env_pearson) << m;
        EXPECT_LT(h.env_mse, b.env_mse) << m;
      }
    }
    // Extrapolations: the envelope above the physics alone and the data-only map (the
    // transported baselines are the close competitors there: docs/hybrid.md).
    EXPECT_GT(h.env_pearson, r.model("physics").env_pearson);
    EXPECT_GT(h.env_pearson, r.model("data_only").env_pearson);
    EXPECT_GT(r.band_coverage_log, 0.5);
    EXPECT_GT(r.band_coverage_env, 0.5);
    cover_log += r.band_coverage_log / static_cast<double>(res.rows.size());
    cover_env += r.band_coverage_env / static_cast<double>(res.rows.size());
  }
  // The band's nominal coverage is 80 %: on the held-out points it covers 70-95 % of the bins.
  std::printf("mean band coverage: log %.3f, envelope %.3f (nominal %.2f)\n", cover_log, cover_env, hy::k_band_coverage);
  EXPECT_GT(cover_log, 0.7);
  EXPECT_LT(cover_log, 0.95);
  EXPECT_GT(cover_env, 0.7);
  EXPECT_LT(cover_env, 0.95);
  for (double t : res.train_wall_s) std::printf("fold training wall time %.2f s\n", t);

  const std::string dir = amb::test::artefact_dir();
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/hybrid_leave_one_out.json") << hy::loo_json(res).dump(2) << '\n';
}

// Training is seeded and reproducible: the same records and seed give the same model file bit
// for bit (two threads); another seed gives another file (the simulated sensor noise and the
// ensemble's bootstrap change); the file predicts what the trained model does.
TEST(HybridLeaveOneOut, SameSeedSameModelFileBitForBit) {
  auto recs = nine_records();
  recs.erase(recs.begin() + 6, recs.end());  // 1797 and 1750 rpm
  hy::TrainOptions o;
  o.threads = 2;
  const std::string dir = amb::test::artefact_dir();
  std::filesystem::create_directories(dir);
  hy::HybridModel m7;
  auto file_of = [&](uint64_t seed, const std::string& name) {
    o.seed = seed;
    auto m = hy::train_hybrid(recs, o);
    EXPECT_TRUE(m.psd_correction.trained());
    const std::string path = dir + "/" + name;
    hy::save_model(m, path);
    if (seed == 7) m7 = std::move(m);
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string a = file_of(7, "hybrid_repro_a.json"), b = file_of(7, "hybrid_repro_b.json"),
                    c = file_of(8, "hybrid_repro_c.json");
  ASSERT_GT(a.size(), 10000u);
  EXPECT_TRUE(a == b) << "same seed, different model files";
  // The file predicts what the trained model does (corrections, ensemble and band included).
  const auto back = hy::load_model(dir + "/hybrid_repro_b.json");
  ASSERT_TRUE(back.psd_correction.trained() && back.env_correction.trained());
  const auto p1 = hy::predict_hybrid(m7, hy::BearingState::outer_race, {1730.0, 3.0});
  const auto p2 = hy::predict_hybrid(back, hy::BearingState::outer_race, {1730.0, 3.0});
  EXPECT_EQ(p1.hybrid_kind, "correction");
  EXPECT_EQ(p1.log_psd_hybrid, p2.log_psd_hybrid);
  EXPECT_EQ(p1.env_hybrid_hi, p2.env_hybrid_hi);
  EXPECT_EQ(p1.log_psd_hybrid_lo, p2.log_psd_hybrid_lo);
  EXPECT_FALSE(a == c) << "another seed gave the same model file";
}
