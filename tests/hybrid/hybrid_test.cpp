// Hybrid model (seed 001, issue 18): spectra, the learned map, the model file, generated data
// with a known transfer path, and the CWRU records at a held-back speed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "host-tools/core/hybrid/hybrid_model.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "tests/support/test_paths.hpp"

namespace hy = amb::host::hybrid;

namespace {

std::string cwru(const char* f) { return std::string(amb::test::shared_dir()) + "/data/measured/cwru/" + f + ".mat"; }

hy::Record cwru_record(const char* f, hy::BearingState s, double rpm, double load) {
  hy::Record r;
  r.path = cwru(f);
  r.state = s;
  r.op = {rpm, load};
  hy::load_record(r);
  return r;
}

// Known transfer path for generated "measurements": two housing resonances (RBJ peaking
// biquads, +20 dB at 2.8 kHz Q 8 and +12 dB at 1.2 kHz Q 4) and white sensor noise.
std::vector<double> transfer_path(const std::vector<double>& x, double fs, uint64_t seed) {
  auto peak = [&](std::vector<double> v, double f0, double gain_db, double q) {
    const double a = std::pow(10.0, gain_db / 40.0), w = 2 * M_PI * f0 / fs, al = std::sin(w) / (2 * q);
    const double b0 = 1 + al * a, b1 = -2 * std::cos(w), b2 = 1 - al * a, a0 = 1 + al / a, a1 = -2 * std::cos(w),
                 a2 = 1 - al / a;
    double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
    for (double& s : v) {
      const double y = (b0 * s + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2) / a0;
      x2 = x1;
      x1 = s;
      y2 = y1;
      y1 = y;
      s = y;
    }
    return v;
  };
  auto y = peak(peak(x, 2800.0, 20.0, 8.0), 1200.0, 12.0, 4.0);
  double rms = 0;
  for (double v : y) rms += v * v;
  rms = std::sqrt(rms / static_cast<double>(y.size()));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 0.05 * rms);
  for (double& v : y) v += g(rng);
  return y;
}

// The generator's rig differs from the model's (masses, clearance, damping, a 6 deg contact
// angle, noise): the model is never the generator.
hy::RigParams generator_rig() {
  hy::RigParams g;
  g.bearing_mass_kg = 0.7;
  g.disc_mass_kg = 2.6;
  g.radial_clearance_m = 8e-6;
  g.bearing_damping_n_s_per_m = 300.0;
  g.drive_end_contact_angle_rad = 6.0 * M_PI / 180.0;
  g.unbalance_eccentricity_m = 20e-6;
  g.sensor_noise_rel = 0.0;
  return g;
}

hy::Record generated(hy::BearingState s, double rpm, double seconds) {
  hy::Record r;
  r.path = std::string("generated:") + hy::state_name(s) + "@" + std::to_string(static_cast<int>(rpm));
  r.fs_hz = 12000.0;
  r.state = s;
  r.op = {rpm, 0.0};
  const auto x = hy::simulate_drive_end(generator_rig(), s, r.op, r.fs_hz, seconds, 1000 + static_cast<uint64_t>(s));
  r.signal = transfer_path(x, r.fs_hz, 77 + static_cast<uint64_t>(rpm));
  return r;
}

void write_artefact(const std::string& name, const nlohmann::json& j) {
  const std::string dir = amb::test::artefact_dir();
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/" + name) << j.dump(2) << '\n';
}

}  // namespace

TEST(HybridSpectra, GridIsConstantThenProportional) {
  hy::SpectralOptions o;
  const auto g = hy::psd_grid(o);
  ASSERT_GT(g.bins(), 100u);
  EXPECT_DOUBLE_EQ(g.edges.front(), o.psd_min_hz);
  EXPECT_DOUBLE_EQ(g.edges.back(), o.psd_max_hz);
  EXPECT_NEAR(g.edges[1] - g.edges[0], o.psd_bin_min_hz, 1e-9);
  // Above 400 Hz the bins are 1 % wide (2 x the +-0.5 % speed uncertainty).
  for (size_t i = 0; i + 2 < g.bins(); ++i) {
    if (g.edges[i] > 500) {
      EXPECT_NEAR((g.edges[i + 1] - g.edges[i]) / g.edges[i], o.rel_bin_width, 1e-9);
    }
  }
}

TEST(HybridSpectra, LineLandsInItsBinAndScalesWithSpeed) {
  hy::SpectralOptions o;
  const double fs = 12000.0;
  std::vector<double> x(static_cast<size_t>(4 * fs));
  // Carrier at 3 kHz amplitude-modulated at 105 Hz: envelope line at 105 Hz.
  for (size_t i = 0; i < x.size(); ++i) {
    const double t = static_cast<double>(i) / fs;
    x[i] = (1.0 + 0.5 * std::cos(2 * M_PI * 105.0 * t)) * std::cos(2 * M_PI * 3000.0 * t);
  }
  const auto g = hy::env_grid(o);
  auto peak_hz = [&](const std::vector<double>& e) {
    size_t best = 0;
    for (size_t k = 0; k < e.size(); ++k)
      if (e[k] > e[best]) best = k;
    return g.centre_hz(best);
  };
  const auto s = hy::compute_spectra(x, fs, o);
  EXPECT_NEAR(peak_hz(s.env), 105.0, 1.5);
  // The same record read as if the speed were 2 % higher: the line moves to 107.1 Hz.
  const auto s2 = hy::compute_spectra(x, fs, o, {1.02});
  EXPECT_NEAR(peak_hz(s2.env), 107.1, 1.5);
  EXPECT_THROW(hy::compute_spectra(std::vector<double>(100, 0.0), fs, o), std::invalid_argument);
  EXPECT_THROW(hy::compute_spectra(x, 8000.0, o), std::invalid_argument);  // Nyquist below the grid
}

TEST(HybridSpectra, MoveWithSpeedShiftsLinesAndKeepsTheRest) {
  hy::SpectralOptions o;
  const auto g = hy::env_grid(o);
  std::vector<double> c(g.bins()), y(g.bins(), 1.0);
  for (size_t k = 0; k < c.size(); ++k) c[k] = g.centre_hz(k);
  size_t line = 0;  // the bin holding 105 Hz
  while (g.edges[line + 1] <= 105.0) ++line;
  y[line] = 50.0;
  const auto moved = hy::move_with_speed(y, c, 1.2);  // 105 Hz -> 126 Hz
  size_t best = 0;
  for (size_t k = 0; k < moved.size(); ++k)
    if (moved[k] > moved[best]) best = k;
  EXPECT_NEAR(c[best], 126.0, 1.5);
  EXPECT_LT(moved[line], 2.0);  // the old position is back at the floor
  EXPECT_EQ(hy::move_with_speed(y, c, 1.0), y);
  EXPECT_THROW(hy::move_with_speed(y, c, 10.0), std::invalid_argument);
  const auto lm = hy::local_mean({0, 0, 3, 0, 0}, 1);
  EXPECT_DOUBLE_EQ(lm[2], 1.0);
  EXPECT_DOUBLE_EQ(lm[0], 0.0);
}

TEST(HybridSpectra, SplitHalfReliabilityFallsWithNoise) {
  // A stationary record (lines + broadband noise) is reliable; the same record shortened to
  // the minimum length with the line buried in more noise is less so.
  hy::SpectralOptions o;
  const double fs = 12000.0;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n(0.0, 1.0);
  auto make = [&](double seconds, double noise) {
    std::vector<double> x(static_cast<size_t>(seconds * fs));
    for (size_t i = 0; i < x.size(); ++i) {
      const double t = static_cast<double>(i) / fs;
      x[i] = (1.0 + 0.5 * std::cos(2 * M_PI * 105.0 * t)) * std::cos(2 * M_PI * 3000.0 * t) + noise * n(rng);
    }
    return x;
  };
  const auto good = hy::split_half_reliability(make(8.0, 0.3), fs, o);
  const auto poor = hy::split_half_reliability(make(4.0, 3.0), fs, o);
  EXPECT_GT(good.env_half, 0.95);
  EXPECT_LT(poor.env_half, good.env_half);
  EXPECT_NEAR(good.env_full, 2 * good.env_half / (1 + good.env_half), 1e-12);
  EXPECT_THROW(hy::split_half_reliability(make(3.0, 0.1), fs, o), std::invalid_argument);
}

TEST(HybridSpectra, Pearson) {
  EXPECT_NEAR(hy::pearson({1, 2, 3}, {2, 4, 6}), 1.0, 1e-12);
  EXPECT_NEAR(hy::pearson({1, 2, 3}, {3, 2, 1}), -1.0, 1e-12);
  EXPECT_EQ(hy::pearson({1, 1, 1}, {1, 2, 3}), 0.0);
  EXPECT_THROW(hy::pearson({1, 2}, {1, 2, 3}), std::invalid_argument);
}

TEST(HybridPhysics, DefectLinesAtKinematicFrequencies) {
  hy::RigParams rig;
  hy::SpectralOptions o;
  const auto g = hy::env_grid(o);
  const double rpm = 1797.0;
  struct Case {
    hy::BearingState s;
    double order;
  } cases[] = {{hy::BearingState::outer_race, 3.5848}, {hy::BearingState::inner_race, 5.4152}};
  for (const auto& c : cases) {
    const auto x = hy::simulate_drive_end(rig, c.s, {rpm, 0.0}, 12000.0, 2.0, 3);
    const auto s = hy::compute_spectra(x, 12000.0, o);
    const double f = c.order * rpm / 60.0;
    size_t best = 0;  // strongest envelope bin between 0.8 and 1.2 x the defect line
    for (size_t k = 0; k < s.env.size(); ++k)
      if (g.centre_hz(k) > 0.8 * f && g.centre_hz(k) < 1.2 * f && (best == 0 || s.env[k] > s.env[best])) best = k;
    EXPECT_NEAR(g.centre_hz(best), f, 0.015 * f) << hy::state_name(c.s);
  }
  hy::RigParams bad = rig;
  bad.drive_end_bearing = "nonesuch";
  EXPECT_THROW(hy::simulate_drive_end(bad, hy::BearingState::healthy, {1797, 0}, 12000, 1, 1), std::invalid_argument);
  EXPECT_THROW(hy::parse_state("cracked"), std::invalid_argument);
  EXPECT_EQ(hy::parse_state("IR"), hy::BearingState::inner_race);
}

TEST(HybridMap, LearnsBandGainAndIgnoresConstantInputs) {
  // y = 2 + 0.5 q on a toy grid: the map must reproduce it; the speed never varies in training
  // and must be ignored (not extrapolated) at another speed.
  std::vector<double> grid;
  for (int k = 0; k < 60; ++k) grid.push_back(10.0 + 10.0 * k);
  std::vector<hy::MapInput> in;
  std::vector<std::vector<double>> y;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 12; ++i) {
    hy::MapInput m;
    m.state = i % 4;
    m.op = {1797.0, 0.0};
    std::vector<double> q(grid.size()), t(grid.size());
    for (size_t k = 0; k < grid.size(); ++k) {
      q[k] = n(rng);
      t[k] = 2.0 + 0.5 * q[k];
    }
    m.physics = {q};
    in.push_back(m);
    y.push_back(t);
  }
  hy::SpectralMapOptions o;
  o.split_local = false;
  o.lambda_physics = 1e-6;
  o.lambda_transfer = 1e-6;
  hy::SpectralMap map;
  map.train(in, y, grid, o);
  EXPECT_LT(map.training_rms(), 1e-3);
  hy::MapInput probe = in[0];
  probe.op = {1500.0, 3.0};
  const auto p = map.predict(probe);
  for (size_t k = 0; k < grid.size(); ++k) EXPECT_NEAR(p[k], y[0][k], 1e-2);
  const auto back = hy::SpectralMap::from_json(map.to_json());
  EXPECT_EQ(back.predict(probe), p);
  probe.physics.clear();
  EXPECT_THROW(map.predict(probe), std::invalid_argument);
}

namespace {

// Every bearing state of the generated data.
const hy::BearingState k_generated_states[] = {hy::BearingState::healthy, hy::BearingState::inner_race,
                                               hy::BearingState::outer_race, hy::BearingState::ball};

// One state of a generated case: the prediction at the held-back speed and its scores.
struct GeneratedOutcome {
  hy::BearingState state;
  hy::Prediction prediction;
  hy::Scores scores;
};

// Train with `o` on the generated records of every state at 1500 rpm, predict each state at
// 1800 rpm and score it against the generated "measurement" there.
std::vector<GeneratedOutcome> train_1500_predict_1800(const hy::TrainOptions& o) {
  std::vector<hy::Record> train;
  for (auto s : k_generated_states) train.push_back(generated(s, 1500.0, 4.0));
  const auto m = hy::train_hybrid(train, o);
  std::vector<GeneratedOutcome> out;
  for (auto s : k_generated_states) {
    const auto truth = generated(s, 1800.0, 4.0);
    auto p = hy::predict_hybrid(m, s, truth.op);
    const auto c = hy::score(p, hy::measured_spectra(m, truth));
    out.push_back({s, std::move(p), c});
  }
  return out;
}

}  // namespace

// Generated data with a known transfer path: "measurements" from a different rig through two
// housing resonances; train at 1500 rpm, predict at 1800 rpm, every state.
TEST(HybridGenerated, KnownTransferPathCarriesToAnotherSpeed) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [s, p, c] : train_1500_predict_1800(hy::TrainOptions{})) {
    std::printf("generated %-10s 1800 rpm  log spectrum: hybrid %.3f physics %.3f data %.3f | envelope: hybrid %.3f "
                "physics %.3f data %.3f\n",
                hy::state_name(s), c.log_psd_hybrid, c.log_psd_physics, c.log_psd_data_only, c.env_hybrid,
                c.env_physics, c.env_data_only);
    out.push_back({{"state", hy::state_name(s)},
                   {"log_spectrum", {{"hybrid", c.log_psd_hybrid}, {"physics", c.log_psd_physics}, {"data_only", c.log_psd_data_only}}},
                   {"envelope_spectrum", {{"hybrid", c.env_hybrid}, {"physics", c.env_physics}, {"data_only", c.env_data_only}}}});
    // The transfer path is learned: the hybrid's log spectrum is above the physics alone (no
    // transfer path) and the data alone (lines at the training speed) in every state.
    EXPECT_GT(c.log_psd_hybrid, 0.75) << hy::state_name(s);
    EXPECT_GT(c.log_psd_hybrid, c.log_psd_physics) << hy::state_name(s);
    EXPECT_GT(c.log_psd_hybrid, c.log_psd_data_only) << hy::state_name(s);
    if (s != hy::BearingState::healthy) {  // the healthy envelope holds only the 1x line and noise
      EXPECT_GT(c.env_hybrid, c.env_data_only) << hy::state_name(s);
      // Envelope: the generator's lines are the model's lines (same kinematics after the
      // calibration), so the map adds little; it must not lose more than 0.05 (docs/hybrid.md).
      EXPECT_GT(c.env_hybrid, c.env_physics - 0.05) << hy::state_name(s);
    }
  }
  write_artefact("hybrid_generated.json", out);
}

// Ablation behind the transport default (docs/hybrid.md, "Ablations"): the same generated
// case with the transported training spectrum as a second physics input of the envelope map.
TEST(HybridGenerated, TransportAblation) {
  hy::TrainOptions o;
  o.transport_env = true;
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [s, p, c] : train_1500_predict_1800(o)) {
    std::printf("generated %-10s 1800 rpm, transport on the envelope | envelope: hybrid %.3f (8-DOF-only map %.3f, "
                "transport alone %.3f) physics %.3f data %.3f\n",
                hy::state_name(s), c.env_hybrid, c.env_hybrid_sim, c.env_transport, c.env_physics, c.env_data_only);
    out.push_back({{"state", hy::state_name(s)},
                   {"envelope_spectrum", {{"hybrid_transport", c.env_hybrid}, {"hybrid_8dof_only", c.env_hybrid_sim},
                                          {"transport_only", c.env_transport}, {"physics", c.env_physics},
                                          {"data_only", c.env_data_only}}}});
    EXPECT_EQ(p.reference, std::string(hy::state_name(s)) + "@1500rpm/0");
    // The log-PSD map has no transport input here: it is the 8-DOF-only map.
    EXPECT_EQ(p.log_psd_hybrid, p.log_psd_hybrid_sim);
    // Moved lines are where the generator put them: far above the unmoved data-only model.
    if (s != hy::BearingState::healthy) {
      EXPECT_GT(c.env_transport, c.env_data_only + 0.3) << hy::state_name(s);
      EXPECT_GT(c.env_hybrid, c.env_data_only + 0.3) << hy::state_name(s);
    }
  }
  write_artefact("hybrid_generated_transport.json", out);
}

// Trained at two speeds (1500 and 2100 rpm), predicted at 1800 rpm: the transport input of a
// training segment is then the other speed's spectrum moved to its speed (cross-fitted across
// operating points), so the map sees real speed changes. Default hybrid and hybrid with
// transport side by side (docs/hybrid.md).
TEST(HybridGenerated, TwoTrainingSpeedsTransportCrossFitted) {
  const hy::BearingState states[] = {hy::BearingState::healthy, hy::BearingState::inner_race,
                                     hy::BearingState::outer_race, hy::BearingState::ball};
  std::vector<hy::Record> train;
  for (double rpm : {1500.0, 2100.0})
    for (auto s : states) train.push_back(generated(s, rpm, 4.0));
  hy::TrainOptions def;
  // The learned map and its transport input (issue 18) are what is compared here: without the
  // issue-34 correction, which two training speeds would otherwise make the hybrid.
  def.correction = false;
  hy::TrainOptions tr = def;
  tr.transport_env = tr.transport_log_psd = true;
  const auto md = hy::train_hybrid(train, def);
  const auto mt = hy::train_hybrid(train, tr);
  // The issue-34 hybrid on the same data (the correction of the interpolated transport, default
  // options): printed and written for docs/hybrid.md, its own claims are tested on CWRU.
  const auto mc = hy::train_hybrid(train, hy::TrainOptions{});
  nlohmann::json out = nlohmann::json::array();
  for (auto s : states) {
    const auto truth = generated(s, 1800.0, 4.0);
    {
      const auto table = hy::score_table(hy::predict_hybrid(mc, s, truth.op), hy::measured_spectra(mc, truth));
      std::printf("generated %-10s issue-34 models, Pearson log | env:", hy::state_name(s));
      nlohmann::json row = {{"state", hy::state_name(s)}, {"issue_34", true}};
      for (const auto& r : table) {
        std::printf(" %s %.3f | %.3f;", r.model.c_str(), r.log_pearson, r.env_pearson);
        row[r.model] = {{"log_spectrum", r.log_pearson}, {"envelope_spectrum", r.env_pearson}};
      }
      std::printf("\n");
      out.push_back(row);
    }
    const auto meas = hy::measured_spectra(md, truth);
    const auto cd = hy::score(hy::predict_hybrid(md, s, truth.op), meas);
    const auto pt = hy::predict_hybrid(mt, s, truth.op);
    const auto ct = hy::score(pt, meas);
    std::printf("generated %-10s 1500+2100 -> 1800 rpm | log: hybrid %.3f, +transport %.3f (alone %.3f) physics %.3f "
                "data %.3f | env: hybrid %.3f, +transport %.3f (alone %.3f) physics %.3f data %.3f\n",
                hy::state_name(s), cd.log_psd_hybrid, ct.log_psd_hybrid, ct.log_psd_transport, cd.log_psd_physics,
                cd.log_psd_data_only, cd.env_hybrid, ct.env_hybrid, ct.env_transport, cd.env_physics, cd.env_data_only);
    out.push_back({{"state", hy::state_name(s)},
                   {"log_spectrum", {{"hybrid", cd.log_psd_hybrid}, {"hybrid_transport", ct.log_psd_hybrid},
                                     {"transport_only", ct.log_psd_transport}, {"physics", cd.log_psd_physics},
                                     {"data_only", cd.log_psd_data_only}}},
                   {"envelope_spectrum", {{"hybrid", cd.env_hybrid}, {"hybrid_transport", ct.env_hybrid},
                                          {"transport_only", ct.env_transport}, {"physics", cd.env_physics},
                                          {"data_only", cd.env_data_only}}}});
    // Two training speeds: the speed input is learned; the default hybrid's log spectrum is
    // above both baselines in every state.
    EXPECT_GT(cd.log_psd_hybrid, std::max(cd.log_psd_physics, cd.log_psd_data_only)) << hy::state_name(s);
    // Cross-fitted, the transport input adds to the log spectrum in every state (docs/hybrid.md).
    EXPECT_GT(ct.log_psd_hybrid, cd.log_psd_hybrid) << hy::state_name(s);
    EXPECT_EQ(pt.reference, std::string(hy::state_name(s)) + "@2100rpm/0");  // nearer in log speed ratio
  }
  write_artefact("hybrid_generated_two_speeds.json", out);
}

// The CWRU records: train at 1797 rpm (0 hp; healthy, inner, outer, ball), predict at the
// held-back 1750 rpm (2 hp; inner and outer race are recorded there).
TEST(HybridCwru, HeldBackSpeedHybridAboveBothBaselines) {
  std::vector<hy::Record> train = {
      cwru_record("1797_Normal", hy::BearingState::healthy, 1797, 0),
      cwru_record("1797_IR_7_DE12", hy::BearingState::inner_race, 1797, 0),
      cwru_record("1797_ORat6_7_DE12", hy::BearingState::outer_race, 1797, 0),
      cwru_record("1797_B_7_DE12", hy::BearingState::ball, 1797, 0),
  };
  hy::TrainOptions o;
  const auto t0 = std::chrono::steady_clock::now();
  const auto m = hy::train_hybrid(train, o);
  const double train_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Kinematic calibration: a loaded 6205 runs at a small contact angle (OR lines above, IR below the catalogue).
  EXPECT_EQ(m.calibration.lines_used, 2);
  EXPECT_GT(m.calibration.contact_angle_rad * 180 / M_PI, 3.0);
  EXPECT_LT(m.calibration.contact_angle_rad * 180 / M_PI, 20.0);

  // Model file round trip: same predictions; another version is refused.
  const std::string path = std::string(amb::test::artefact_dir()) + "/hybrid_cwru_1797.json";
  std::filesystem::create_directories(amb::test::artefact_dir());
  hy::save_model(m, path);
  const auto back = hy::load_model(path);

  nlohmann::json out = nlohmann::json::array();
  struct Held {
    const char* file;
    hy::BearingState s;
  } held[] = {{"1750_IR_7_DE12", hy::BearingState::inner_race}, {"1750_ORat6_7_DE12", hy::BearingState::outer_race}};
  for (const auto& h : held) {
    const auto truth = cwru_record(h.file, h.s, 1750, 2);
    const auto t1 = std::chrono::steady_clock::now();
    const auto p = hy::predict_hybrid(back, h.s, truth.op);
    const double predict_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    EXPECT_EQ(p.log_psd_hybrid, hy::predict_hybrid(m, h.s, truth.op).log_psd_hybrid);
    const auto c = hy::score(p, hy::measured_spectra(back, truth));
    // The comparison quantity is a model figure, not an estimator figure: the measured record's
    // two halves agree to well above every model's score (split-half reliability), so the
    // estimation variance of the Welch spectra does not cap the Pearson figures.
    const auto rel = hy::split_half_reliability(truth.signal, truth.fs_hz, back.options.spectra);
    std::printf("CWRU %-10s 1750 rpm  log spectrum: hybrid %.3f physics %.3f data %.3f | envelope: hybrid %.3f "
                "physics %.3f data %.3f | predict %.2f s\n"
                "     ablations: log 8-DOF-only map %.3f, transport %.3f | env 8-DOF-only map %.3f, transport %.3f | "
                "split-half reliability log %.4f env %.4f\n",
                hy::state_name(h.s), c.log_psd_hybrid, c.log_psd_physics, c.log_psd_data_only, c.env_hybrid,
                c.env_physics, c.env_data_only, predict_s, c.log_psd_hybrid_sim, c.log_psd_transport, c.env_hybrid_sim,
                c.env_transport, rel.log_psd_half, rel.env_half);
    out.push_back({{"state", hy::state_name(h.s)},
                   {"log_spectrum", {{"hybrid", c.log_psd_hybrid}, {"physics", c.log_psd_physics}, {"data_only", c.log_psd_data_only},
                                     {"transport_only", c.log_psd_transport}}},
                   {"envelope_spectrum", {{"hybrid", c.env_hybrid}, {"physics", c.env_physics}, {"data_only", c.env_data_only},
                                          {"transport_only", c.env_transport}}},
                   {"split_half_reliability", {{"log_spectrum", rel.log_psd_half}, {"envelope_spectrum", rel.env_half}}},
                   {"reference", p.reference},
                   {"predict_s", predict_s}});
    EXPECT_GT(rel.log_psd_half, 0.98) << h.file;
    EXPECT_GT(rel.env_half, 0.98) << h.file;
    EXPECT_GT(rel.log_psd_half, c.log_psd_hybrid + 0.05) << h.file;
    EXPECT_EQ(p.reference, std::string(hy::state_name(h.s)) + "@1797rpm/0");
    EXPECT_GT(c.log_psd_hybrid, c.log_psd_physics) << h.file;
    EXPECT_GT(c.log_psd_hybrid, c.log_psd_data_only) << h.file;
    EXPECT_GT(c.env_hybrid, c.env_physics) << h.file;
    EXPECT_GT(c.env_hybrid, c.env_data_only) << h.file;
    // Seed 001 reports 0.95 (outer race, held-back speed). Not reached here: docs/hybrid.md
    // says why (nominal-speed uncertainty and load change at 1750 rpm). Floors guard regressions.
    EXPECT_GT(c.log_psd_hybrid, 0.85) << h.file;
    EXPECT_GT(c.env_hybrid, 0.6) << h.file;
  }
  std::printf("CWRU training wall time %.2f s (%d threads)\n", train_s, o.threads);
  write_artefact("hybrid_cwru_1797_to_1750.json", {{"train_s", train_s}, {"threads", o.threads}, {"held_back", out}});

  // A model file of another version is refused with a message naming it.
  nlohmann::json j;
  std::ifstream(path) >> j;
  j["version"] = 99;
  const std::string bad = path + ".v99";
  std::ofstream(bad) << j.dump();
  try {
    hy::load_model(bad);
    FAIL() << "version 99 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("version 99"), std::string::npos) << e.what();
  }
}

TEST(HybridCwru, TrainingIsDeterministicForASeed) {
  std::vector<hy::Record> train = {cwru_record("1797_IR_7_DE12", hy::BearingState::inner_race, 1797, 0),
                                   cwru_record("1797_ORat6_7_DE12", hy::BearingState::outer_race, 1797, 0)};
  hy::TrainOptions o;
  o.sim_duration_s = 2.0;
  const auto a = hy::train_hybrid(train, o);
  o.threads = 1;  // and independent of the thread count
  const auto b = hy::train_hybrid(train, o);
  EXPECT_EQ(a.psd_hybrid.to_json().dump(), b.psd_hybrid.to_json().dump());
  EXPECT_EQ(a.env_hybrid.to_json().dump(), b.env_hybrid.to_json().dump());
  EXPECT_EQ(a.env_data_only.to_json().dump(), b.env_data_only.to_json().dump());
}
