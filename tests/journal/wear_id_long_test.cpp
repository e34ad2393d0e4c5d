// Seed 002's identification on SIL data (label `long`): the three machined wears of Table 2
// at static eccentricities 0.1 and 0.7, recorded in software in the loop with probe noise,
// identified with the three-parameter (elliptical) and the two-parameter model. The
// identification reads the written event files only.
//  - 3p: within 5 % on d0 and beta and 3 deg on gamma in every case (the seed's Tables 5-6
//    report errors up to 21 %, 46 % on gamma);
//  - 2p: the seed's finding: wear 1 (machined with the 2p proportion) is found, wears 2 and 3
//    reach a low cost with wrong parameters.
// Run: ctest -L long -R journal_wear  (or build-*/tests/journal/journal_wear_id_tests)
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "firmware/board/board.hpp"
#include "host-tools/core/events/load_event.hpp"
#include "host-tools/core/wearid/journal_sil_record.hpp"
#include "host-tools/core/wearid/journal_spectrum.hpp"
#include "host-tools/core/wearid/rig_response.hpp"
#include "model/journal/journal_rig.hpp"
#include "model/journal/reynolds_fvm.hpp"
#include "model/rotor/rotor_model.hpp"
#include "host-tools/core/wearid/wear_identification.hpp"
#include "tests/journal/table2_wears.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;
namespace mj = amb::model::journal;
namespace wi = amb::host::wearid;

namespace {
constexpr double k_deg = M_PI / 180.0;
using Wear = amb::test::journal::Table2Wear;
constexpr auto& k_wears = amb::test::journal::k_table2_wears;  // seed 002 Table 2

std::string record(const Wear& w, double ecc, int seed, const char* tag = "", double full_film_s = 0.0,
                   double record_s = 2.0) {
  const std::string dir = std::string(test::artefact_dir()) + "/journal_wear";
  std::filesystem::create_directories(dir);
  char stem[256];
  std::snprintf(stem, sizeof stem, "%s/%s%s_e%02d", dir.c_str(), tag, w.tag,
                static_cast<int>(std::lround(ecc * 10)));
  wi::JournalSilOptions o;
  o.eccentricity = ecc;
  o.wear = {mj::WearModel::elliptical, w.d0_um * 1e-6, w.gamma_deg * k_deg, w.beta_deg * k_deg};
  o.noise_seed = static_cast<std::uint64_t>(seed);
  o.full_film_s = full_film_s;
  o.record_s = record_s;
  const wi::JournalSilSummary s = wi::record_journal_sil(o, stem);
  EXPECT_TRUE(s.ok) << s.message;
  // With the full film the journal sits where the film's mean force over the orbit (not its
  // static force at the set point, which the placement uses) balances the rotor: at e = 0.1,
  // where the film is soft, that moved it to e = 0.092-0.120 (seed 1); the identification uses
  // the measured mean position. The check there is that the journal stays near the set point.
  EXPECT_NEAR(s.static_eccentricity, ecc, full_film_s > 0.0 ? 0.03 : 0.02);
  return std::string(stem) + ".json";
}
}  // namespace

TEST(JournalWearId, SeedTable2WearsFromSilAtBothEccentricities) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  std::printf("| e | wear | truth d0/gamma/beta | 3p d0 | 3p gamma | 3p beta | 3p cost | 2p d0 | 2p gamma | 2p beta (implied) | 2p cost | 3p s | 2p s |\n");
  int seed = 11;
  for (double ecc : {0.1, 0.7}) {
    for (const Wear& w : k_wears) {
      const std::string path = record(w, ecc, seed++);
      const wi::JournalMeasurement m = wi::measure_journal(host::load_event(path), b);
      wi::WearIdOptions o3;
      o3.model = mj::WearModel::elliptical;
      const wi::WearIdResult r3 = wi::identify_wear(b, m, o3);
      wi::WearIdOptions o2 = o3;
      o2.model = mj::WearModel::two_parameter;
      const wi::WearIdResult r2 = wi::identify_wear(b, m, o2);
      std::printf("| %.1f | %s | %.2f / %.1f / %.0f | %.2f +- %.2f (%+.1f %%) | %.2f +- %.2f (%+.2f deg) | %.2f +- %.2f (%+.1f %%) | %.1e | "
                  "%.2f (%+.1f %%) | %.2f (%+.2f deg) | %.2f (%+.1f %%) | %.1e | %.1f | %.1f |\n",
                  ecc, w.name, w.d0_um, w.gamma_deg, w.beta_deg, r3.d0_um, r3.d0_uncertainty_um,
                  100 * (r3.d0_um / w.d0_um - 1), r3.gamma_deg, r3.gamma_uncertainty_deg, r3.gamma_deg - w.gamma_deg,
                  r3.beta_deg, r3.beta_uncertainty_deg, 100 * (r3.beta_deg / w.beta_deg - 1), r3.cost, r2.d0_um,
                  100 * (r2.d0_um / w.d0_um - 1), r2.gamma_deg, r2.gamma_deg - w.gamma_deg, r2.beta_deg,
                  100 * (r2.beta_deg / w.beta_deg - 1), r2.cost, r3.wall_s, r2.wall_s);
      std::fflush(stdout);
      EXPECT_LT(std::abs(r3.d0_um / w.d0_um - 1.0), 0.05) << w.name << " e " << ecc;
      EXPECT_LT(std::abs(r3.beta_deg / w.beta_deg - 1.0), 0.05) << w.name << " e " << ecc;
      EXPECT_LT(std::abs(r3.gamma_deg - w.gamma_deg), 3.0) << w.name << " e " << ecc;
      if (w.name[5] != '1') {
        // The 2p model cannot have this depth with this span: wrong parameters...
        const bool wrong = std::abs(r2.d0_um / w.d0_um - 1.0) > 0.2 || std::abs(r2.beta_deg / w.beta_deg - 1.0) > 0.2;
        EXPECT_TRUE(wrong) << w.name << " e " << ecc;
      }
    }
  }
}

// Seed 002 measures each wear at both static eccentricities. At e = 0.7 alone wear 3 (and,
// with the probes 60 mm inboard, wear 1) is not identifiable (docs/journal-bearing.md: a
// second wear fits the record better than the truth); the e = 0.7 record fitted together with
// the e = 0.1 record of the same bearing is within the targets for every wear.
TEST(JournalWearId, BothEccentricitiesTogetherWithinTargets) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  int seed = 41;
  for (const Wear& w : k_wears) {
    std::vector<wi::JournalMeasurement> ms;
    for (double ecc : {0.7, 0.1}) ms.push_back(wi::measure_journal(host::load_event(record(w, ecc, seed++, "joint_")), b));
    wi::WearIdOptions o;
    o.model = mj::WearModel::elliptical;
    const wi::WearIdResult r = wi::identify_wear(b, ms, o);
    std::printf("[ RESULT ] %s, e 0.7 + 0.1: d0 %.2f (%+.1f %%), gamma %.2f (%+.2f deg), beta %.2f (%+.1f %%), cost %.2e, %.1f s\n",
                w.name, r.d0_um, 100 * (r.d0_um / w.d0_um - 1), r.gamma_deg, r.gamma_deg - w.gamma_deg, r.beta_deg,
                100 * (r.beta_deg / w.beta_deg - 1), r.cost, r.wall_s);
    EXPECT_EQ(r.records, 2);
    EXPECT_LT(std::abs(r.d0_um / w.d0_um - 1.0), 0.05) << w.name;
    EXPECT_LT(std::abs(r.beta_deg / w.beta_deg - 1.0), 0.05) << w.name;
    EXPECT_LT(std::abs(r.gamma_deg - w.gamma_deg), 3.0) << w.name;
  }
}

// The same wears with the full (nonlinear) Reynolds film in the plant (the linear element is
// exact to first order only: at e = 0.7 the unbalance orbit moves the 1x by ~10 % and adds
// +-2x components of ~0.3-0.8 um), recorded as seed 002 acquires them (5 x 5 s: one 25 s
// record, all of it analysed), identified from each record alone with the full-film forward
// model (harmonic balance up to the 3x, with the AMBs' force law), the +-2x components in the
// cost and the 1x residuals' model-error floor of 0.25 % (the frequency model's 1x mismatch to
// the SIL, measured on unworn records). Same noise seeds as
// SeedTable2WearsFromSilAtBothEccentricities. docs/journal-bearing.md, "The nonlinear film at
// e = 0.7" and "The 3x".
TEST(JournalWearId, FullFilmRecordsAloneWithThe2xWithinTargets) {
  const board::BoardConfig b = board::load_board("unicamp-journal-rig");
  int seed = 11;
  for (double ecc : {0.1, 0.7}) {
    for (const Wear& w : k_wears) {
      const std::string path = record(w, ecc, seed++, "full_film_25s_", 8.0, 25.0);
      const wi::JournalMeasurement m = wi::measure_journal(host::load_event(path), b, 25.0);
      wi::WearIdOptions o;
      o.model = mj::WearModel::elliptical;
      o.full_film = true;
      o.second_harmonic = true;
      o.model_error_1x = 0.0025;
      o.window_s = 25.0;
      o.amb_nonlinear = true;
      o.film_harmonics = 3;
      const wi::WearIdResult r = wi::identify_wear(b, m, o);
      std::printf("[ RESULT ] full film, e %.1f (record %.3f), %s: d0 %.2f +- %.2f (%+.1f %%), gamma %.2f +- %.2f (%+.2f deg), "
                  "beta %.2f +- %.2f (%+.1f %%), cost %.2e, %d evaluations, %.1f s\n",
                  ecc, m.eccentricity, w.name, r.d0_um, r.d0_uncertainty_um, 100 * (r.d0_um / w.d0_um - 1), r.gamma_deg,
                  r.gamma_uncertainty_deg, r.gamma_deg - w.gamma_deg, r.beta_deg, r.beta_uncertainty_deg,
                  100 * (r.beta_deg / w.beta_deg - 1), r.cost, r.evaluations, r.wall_s);
      std::fflush(stdout);
      EXPECT_TRUE(r.used_full_film && r.used_second_harmonic);
      EXPECT_NEAR(r.measured.window_s, 25.0, 0.1);
      EXPECT_LT(std::abs(r.d0_um / w.d0_um - 1.0), 0.05) << w.name << " e " << ecc;
      EXPECT_LT(std::abs(r.beta_deg / w.beta_deg - 1.0), 0.05) << w.name << " e " << ecc;
      EXPECT_LT(std::abs(r.gamma_deg - w.gamma_deg), 3.0) << w.name << " e " << ecc;
    }
  }
}

// Seed 002's first critical speed, "around 31 Hz" (section 3, Fig. 6: unbalance response at
// the journal, 10-50 Hz, read off the figure). The ~31 Hz mode is the rotor's first bending
// mode with the AMBs close to its nodes, so the peak tells where the AMB loop measures the
// rotor: with the probes 60 mm inboard of the AMBs (the board before issue 17's third round)
// it was at 37.0 Hz; with the probes at the AMB planes, as in the seed's model (eq. 19 feeds
// back the displacement at nodes 7 and 19), at 32.25 Hz. Two checks:
//  1. the board's closed loop (discrete PID on the linearised force law, RigResponse) and the
//     seed's own linear AMB model (section 2.4: K_AMB1 0.848e6 N/m, C_AMB1 4000 N s/m at
//     node 7, K_AMB2 1.272e6 N/m, C_AMB2 6000 N s/m at node 19) on the same FE rotor and film
//     peak within 1 Hz of each other (the board's loop is the seed's rig, not a retuned one);
//  2. the peak lies within 31 +- 2 Hz: the seed's value is read off a 10-50 Hz plot and called
//     "around"; the seed's model on this rotor gives 32.5 Hz. Probes 20 mm inboard (34.0 Hz) or
//     30 mm outboard (28.75 Hz) already fail it.
namespace {
// Peak of |(x, y)| at the journal, 10-50 Hz in 0.25 Hz steps, of the seed's linear model:
// full FE rotor, springs and dampers at the AMB planes, the film at the journal (K ~ speed).
double seed_spring_model_peak_hz(const board::BoardConfig& b, const mj::DynamicCoefficients& d, double w0) {
  using cd = std::complex<double>;
  const auto fe = model::rotor::build_rotor_model(b.plant.rotor);
  const int n_nodes = fe.node_count, n = 4 * n_nodes;
  auto node = [&](double z) {
    const int k = model::rotor::node_index(fe, z, 1e-4);
    EXPECT_GE(k, 0) << "no node at " << z;
    return k;
  };
  const int nj = node(b.journal.axial_m);
  const double k_amb[2] = {0.848e6, 1.272e6}, c_amb[2] = {4000.0, 6000.0};  // seed 002 section 2.4
  double peak = 0.0, f_peak = 0.0;
  for (double f = 10.0; f <= 50.0; f += 0.25) {
    const double w = 2.0 * M_PI * f, sc = w / w0;
    Eigen::MatrixXd k = fe.K, c = fe.C + w * fe.G;
    for (int a = 0; a < 2; ++a) {
      const int na = node(b.plant.amb[static_cast<size_t>(a)].axial_m);
      for (int plane = 0; plane < 2; ++plane) {
        k(plane * 2 * n_nodes + 2 * na, plane * 2 * n_nodes + 2 * na) += k_amb[a];
        c(plane * 2 * n_nodes + 2 * na, plane * 2 * n_nodes + 2 * na) += c_amb[a];
      }
    }
    for (int r = 0; r < 2; ++r)
      for (int q = 0; q < 2; ++q) {
        k(r * 2 * n_nodes + 2 * nj, q * 2 * n_nodes + 2 * nj) += sc * d.stiffness_n_per_m(r, q);
        c(r * 2 * n_nodes + 2 * nj, q * 2 * n_nodes + 2 * nj) += d.damping_n_s_per_m(r, q);
      }
    const Eigen::MatrixXcd a = k.cast<cd>() - w * w * fe.M.cast<cd>() + cd(0.0, w) * c.cast<cd>();
    // Unbalance as the plant applies it: x amplitude j W^2 u e^{-j phase}, y = -j x (forward).
    Eigen::VectorXcd force = Eigen::VectorXcd::Zero(n);
    for (const auto& disk : b.plant.rotor.disks) {
      if (disk.unbalance_kg_m == 0.0) continue;
      const int nd = node(disk.axial_m);
      const cd fx = cd(0.0, 1.0) * w * w * disk.unbalance_kg_m * std::exp(cd(0.0, -disk.unbalance_phase_deg * k_deg));
      force(2 * nd) += fx;
      force(2 * n_nodes + 2 * nd) += cd(0.0, -1.0) * fx;
    }
    const Eigen::VectorXcd q = a.partialPivLu().solve(force);
    const double amp = std::hypot(std::abs(q(2 * nj)), std::abs(q(2 * n_nodes + 2 * nj)));
    if (amp > peak) {
      peak = amp;
      f_peak = f;
    }
  }
  return f_peak;
}
}  // namespace

TEST(JournalRigLong, FirstCriticalSpeedNearTheSeeds31Hz) {
  // Unbalance response at the journal, 10-50 Hz, film coefficients at each speed from the
  // placed position (K ~ speed, C constant: the homogeneity of journal_rig.hpp).
  board::BoardConfig b = board::load_board("unicamp-journal-rig");
  b.journal.static_eccentricity = 0.1;
  const double w0 = 2.0 * M_PI * 34.0;
  mj::ReynoldsSolver s(b.journal.geometry, {}, b.journal.grid);
  const mj::DynamicCoefficients d = mj::perturbation_coefficients(s, mj::static_journal_state(b.journal), w0);
  wi::RigResponse r(b, 34.0, {d.fx0_n, d.fy0_n});
  double peak = 0.0, f_peak = 0.0, at_50 = 0.0;
  for (double f = 10.0; f <= 50.0; f += 0.25) {
    const double sc = 2.0 * M_PI * f / w0;
    const auto xy = r.journal_xy_at(f, sc * d.stiffness_n_per_m, d.damping_n_s_per_m);
    const double a = std::hypot(std::abs(xy[0]), std::abs(xy[1]));
    if (a > peak) {
      peak = a;
      f_peak = f;
    }
    at_50 = a;
  }
  const double f_seed_model = seed_spring_model_peak_hz(b, d, w0);
  std::printf("[ RESULT ] unbalance response at the journal: peak %.1f um at %.2f Hz (%.1f um at 50 Hz); seed 002's "
              "linear AMB model on this rotor: %.2f Hz (seed 002: first critical ~31 Hz)\n",
              peak * 1e6, f_peak, at_50 * 1e6, f_seed_model);
  EXPECT_GT(f_peak, 10.0);  // a resonance inside the band, not the rising edge
  EXPECT_LT(f_peak, 50.0);
  EXPECT_NEAR(f_peak, f_seed_model, 1.0);
  EXPECT_NEAR(f_peak, 31.0, 2.0);
}
