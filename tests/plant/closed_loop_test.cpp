// The linearised closed loop of both rigs against the seeds' reference numbers: PID-levitated
// natural frequencies (seed 000: 1049, 1252, 2329, 4599 rad/s; seed 002: first critical
// ~31 Hz) and the ISO 14839-3 sensitivity peak. Also: the sampled firmware controller
// (PidAxis + AxisTransform) levitates the nonlinear plant.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"
#include "model/analysis/closed_loop.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "tests/support/firmware_control_law.hpp"
#include "tests/plant/rig_fixture.hpp"

namespace amb::model::analysis {
namespace {

// The firmware's sampled loop (exact discretisation, no computation delay) or the analog PID.
ClosedLoopOptions loop_options(bool sampled, double rate_hz, double delay_periods = 0.0) {
  ClosedLoopOptions o;
  o.sample_rate_hz = sampled ? rate_hz : 0.0;
  o.loop_delay_periods = delay_periods;
  return o;
}

TEST(ClosedLoop, IsoZoneBoundaries) {
  EXPECT_EQ(iso14839_zone(2.99), IsoZone::A);
  EXPECT_EQ(iso14839_zone(3.0), IsoZone::B);
  EXPECT_EQ(iso14839_zone(3.99), IsoZone::B);
  EXPECT_EQ(iso14839_zone(4.5), IsoZone::C);
  EXPECT_EQ(iso14839_zone(5.0), IsoZone::D);
}

// Seed 000: the PID-levitated Bath rotor has natural frequencies 1049 and 1252 rad/s (mainly
// rigid body), 2329 (first bending) and 4599 (second bending). The geometry is assumed (the
// seed gives length and mass only; see the board's [assumed] table), tuned to the first three.
// Bound: 5 % on the first three (what the tuning of an assumed geometry can defend; a
// regression in the FE, the AMB linearisation or the controller model moves them further).
// The second bending mode is reported only: with the cores at the first-bending nodes a
// uniform shaft puts it near 6000 rad/s (no geometry with 4 rigid disks and 6.5 kg matched
// all four without inventing more than the seed says).
TEST(ClosedLoop, BathNaturalFrequenciesMatchSeed000) {
  const auto board = test::board_from_repo("bath-amb-rig");
  const double seed[4] = {1049.0, 1252.0, 2329.0, 4599.0};
  for (bool delay : {false, true}) {
    const ClosedLoopModel cl(board.plant, board.controller, loop_options(delay, board.rate_hz));
    ASSERT_TRUE(cl.stable()) << "sampled " << delay;
    const std::vector<ClosedLoopMode> m = cl.rotor_modes(0.2);
    ASSERT_GE(m.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
      const double err = 100.0 * (m[i].natural_rad_s / seed[i] - 1.0);
      std::printf("[ RESULT ] bath (%s) mode %zu: %.0f seed, %.0f model, err %+.1f %%, zeta %.3f, rotor share %.2f\n",
                  delay ? "sampled" : "continuous", i + 1, seed[i], m[i].natural_rad_s, err,
                  m[i].damping_ratio, m[i].rotor_share);
      if (i < 3) {
        EXPECT_LT(std::abs(err), 5.0) << "mode " << i + 1 << " delay " << delay;
      }
    }
  }
}

// Seed 002: "the first critical speed of the system is around 31 Hz" (measured, with the
// hydrodynamic bearing that this rig leaves out). The lightly damped first mode of the
// AMB-only rotor is its first bending mode; the two rigid-body modes are heavily damped by
// the PID and show no critical speed. Bound: 10 % (the journal bearing at node 25 is missing).
TEST(ClosedLoop, UnicampFirstCriticalNearSeed002) {
  const auto board = test::board_from_repo("unicamp-amb-rig");
  const ClosedLoopModel cl(board.plant, board.controller, ClosedLoopOptions{});
  ASSERT_TRUE(cl.stable());
  const std::vector<ClosedLoopMode> m = cl.rotor_modes(0.3);
  const ClosedLoopMode* critical = nullptr;
  for (const auto& md : m) {
    std::printf("[ RESULT ] unicamp mode: %.1f rad/s = %.2f Hz, zeta %.3f, rotor share %.2f\n", md.natural_rad_s,
                md.natural_rad_s / (2.0 * M_PI), md.damping_ratio, md.rotor_share);
    if (critical == nullptr && md.damping_ratio < 0.1) critical = &md;
  }
  ASSERT_NE(critical, nullptr);
  const double f = critical->natural_rad_s / (2.0 * M_PI);
  std::printf("[ RESULT ] unicamp first critical: 31 Hz seed, %.2f Hz model, err %+.1f %%\n", f, 100.0 * (f / 31.0 - 1.0));
  EXPECT_NEAR(f, 31.0, 3.1);
}

struct ZoneCase {
  const char* board;
  IsoZone expected;   // what the documented gains reach (see docs/plant.md)
  double peak;        // continuous-model peak, for the 5 % band
};

// ISO 14839-3 sensitivity, loop broken at each actuator axis in turn, the others closed,
// 0.1 Hz .. Nyquist. Zone A (< 3) is not reachable for either rig with its seed gains:
//  * Bath: KP / ks = 5.1 / 3.9 leaves a static margin of 1.2 MN/m, so |S| ~ ks / (KP - ks)
//    ~ 3.3 already at low frequency, ~4.6 with the bearing coupling -> zone C;
//  * Unicamp: KP / ks = 1.55 and KD = 5e3 on a 99 kg rotor leave the rigid modes at
//    zeta ~0.24; the peak (~5.2 at 16 Hz) is zone D; no sensor plane or assumed amplifier /
//    filter bandwidth brings it below 4.8 with the seed gains (docs/plant.md).
// The zone reached and a 5 % band on the peak are asserted, so a change that makes it worse fails.
TEST(ClosedLoop, SensitivityPeaksAndIsoZones) {
  for (const ZoneCase& c : {ZoneCase{"bath-amb-rig", IsoZone::C, 4.63}, ZoneCase{"unicamp-amb-rig", IsoZone::D, 5.21}}) {
    const auto board = test::board_from_repo(c.board);
    for (bool delay : {false, true}) {
      const ClosedLoopModel cl(board.plant, board.controller, loop_options(delay, board.rate_hz));
      double worst = 0.0;
      for (int axis = 0; axis < 4; ++axis) {
        const SensitivityPeak p = cl.sensitivity_peak(axis, 0.1, 0.5 * board.rate_hz, 500);
        std::printf("[ RESULT ] %s (%s) axis %d: sensitivity peak %.2f (%.1f dB) at %.1f Hz, zone %s\n", c.board,
                    delay ? "sampled" : "continuous", axis, p.peak, p.peak_db, p.frequency_hz, to_string(p.zone));
        worst = std::max(worst, p.peak);
      }
      std::printf("[ RESULT ] %s (%s): worst sensitivity peak %.2f -> ISO 14839-3 zone %s\n", c.board,
                  delay ? "sampled" : "continuous", worst, to_string(iso14839_zone(worst)));
      if (!delay) {
        EXPECT_EQ(iso14839_zone(worst), c.expected) << c.board << " peak " << worst;
        EXPECT_LT(worst, 1.05 * c.peak) << c.board;
      } else {
        EXPECT_LT(worst, 1.1 * c.peak) << c.board;
      }
    }
  }
}

// The sampled loop with a computation/transport delay against an independent discrete-time
// model of the rigs (issue 38: full Timoshenko rotor, the firmware's PID difference equations
// and notches, exact ZOH; written from the board files, not from this code): ISO 14839-3 peak
// per bearing plane at delay 0 and 1 period. Bath (both planes alike): 4.63 -> 7.38 at 177 Hz;
// Unicamp plane A 5.35 -> 5.67, plane B 4.55 -> 4.79. Bound 5 % (the acceptance band).
// Also prints the table of docs/plant.md (0, 0.5, 1, 1.5 periods).
struct DelayCase {
  const char* board;
  double peak_a[2];  // plane A: delay 0, 1 period
  double peak_b[2];  // plane B
};

TEST(ClosedLoop, SampledLoopWithDelayMatchesIndependentModel) {
  for (const DelayCase& c : {DelayCase{"bath-amb-rig", {4.63, 7.38}, {4.63, 7.38}},
                             DelayCase{"unicamp-amb-rig", {5.35, 5.67}, {4.55, 4.79}}}) {
    const auto board = test::board_from_repo(c.board);
    for (double delay : {0.0, 0.5, 1.0, 1.5}) {
      const ClosedLoopModel cl(board.plant, board.controller, loop_options(true, board.rate_hz, delay));
      double plane[2] = {0.0, 0.0}, at_hz[2] = {0.0, 0.0};
      for (int axis = 0; axis < 4; ++axis) {
        const SensitivityPeak p = cl.sensitivity_peak(axis, 0.1, 0.5 * board.rate_hz, 500);
        if (p.peak > plane[axis / 2]) {
          plane[axis / 2] = p.peak;
          at_hz[axis / 2] = p.frequency_hz;
        }
      }
      const std::vector<ClosedLoopMode> m = cl.rotor_modes(0.2);
      std::printf("[ RESULT ] %s delay %.1f periods: stable %d, plane A %.2f (%.1f dB) at %.0f Hz zone %s, "
                  "plane B %.2f (%.1f dB) at %.0f Hz zone %s; first rotor modes %.0f Hz zeta %.3f, %.0f Hz zeta %.3f\n",
                  c.board, delay, cl.stable(), plane[0], 20.0 * std::log10(plane[0]), at_hz[0],
                  to_string(iso14839_zone(plane[0])), plane[1], 20.0 * std::log10(plane[1]), at_hz[1],
                  to_string(iso14839_zone(plane[1])), m.size() > 0 ? m[0].natural_rad_s / (2 * M_PI) : 0.0,
                  m.size() > 0 ? m[0].damping_ratio : 0.0, m.size() > 1 ? m[1].natural_rad_s / (2 * M_PI) : 0.0,
                  m.size() > 1 ? m[1].damping_ratio : 0.0);
      EXPECT_TRUE(cl.stable()) << c.board << " delay " << delay;
      if (delay == 0.0 || delay == 1.0) {
        const size_t i = delay == 0.0 ? 0 : 1;
        EXPECT_NEAR(plane[0], c.peak_a[i], 0.05 * c.peak_a[i]) << c.board << " plane A, delay " << delay;
        EXPECT_NEAR(plane[1], c.peak_b[i], 0.05 * c.peak_b[i]) << c.board << " plane B, delay " << delay;
      }
    }
  }
}

// The Bath variant tuned for a one-period delay (boards/bath-amb-rig-delay1.toml): zone C or
// better at its own delay (the requirement; it reaches A), every rotor mode damped
// >= 1 %, and stable from 0 to 2 periods (the board key's range).
TEST(ClosedLoop, BathVariantTunedForOnePeriodIsZoneCOrBetter) {
  const auto board = test::board_from_repo("bath-amb-rig-delay1");
  ASSERT_EQ(board.loop_delay_periods, 1.0);
  for (double delay : {0.0, 0.5, 1.0, 1.5, 2.0}) {
    const ClosedLoopModel cl(board.plant, board.controller, loop_options(true, board.rate_hz, delay));
    double worst = 0.0, at_hz = 0.0;
    for (int axis = 0; axis < 4; ++axis) {
      const SensitivityPeak p = cl.sensitivity_peak(axis, 0.1, 0.5 * board.rate_hz, 500);
      if (p.peak > worst) {
        worst = p.peak;
        at_hz = p.frequency_hz;
      }
    }
    double zeta_min = 1.0;
    for (const auto& m : cl.rotor_modes(0.3)) zeta_min = std::min(zeta_min, m.damping_ratio);
    std::printf("[ RESULT ] bath-amb-rig-delay1 delay %.1f periods: stable %d, worst peak %.2f (%.1f dB) at %.0f Hz, zone %s, "
                "least damped rotor mode zeta %.3f\n", delay, cl.stable(), worst, 20.0 * std::log10(worst), at_hz,
                to_string(iso14839_zone(worst)), zeta_min);
    EXPECT_TRUE(cl.stable()) << delay;
    if (delay == 1.0) {
      EXPECT_LT(worst, 5.0);
      EXPECT_GE(zeta_min, 0.01);
    }
  }
}

// Options out of range are refused with the option named.
TEST(ClosedLoop, OptionsOutOfRangeAreRefused) {
  const auto board = test::board_from_repo("bath-amb-rig");
  for (const ClosedLoopOptions& o : {loop_options(true, board.rate_hz, -0.1), loop_options(true, board.rate_hz, 8.5),
                                     loop_options(false, board.rate_hz, 1.0), loop_options(true, -1.0)}) {
    try {
      ClosedLoopModel cl(board.plant, board.controller, o);
      ADD_FAILURE() << "accepted rate " << o.sample_rate_hz << " delay " << o.loop_delay_periods;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(o.sample_rate_hz < 0.0 ? "sample_rate_hz" : "loop_delay_periods"), std::string::npos)
          << e.what();
    }
  }
}

// Spin splits the first bending mode of the Bath rotor into backward and forward whirl.
TEST(ClosedLoop, SpinSplitsWhirlModes) {
  const auto board = test::board_from_repo("bath-amb-rig");
  ClosedLoopOptions o;
  const auto still = ClosedLoopModel(board.plant, board.controller, o).rotor_modes(0.3, 0.0);
  o.spin_hz = 200.0;
  const auto spin = ClosedLoopModel(board.plant, board.controller, o).rotor_modes(0.3, 0.0);
  auto near = [](const std::vector<ClosedLoopMode>& v, double w, double tol) {
    std::vector<double> out;
    for (const auto& m : v)
      if (std::abs(m.natural_rad_s - w) < tol) out.push_back(m.natural_rad_s);
    return out;
  };
  const auto pair0 = near(still, 2329.0, 150.0), pair1 = near(spin, 2329.0, 300.0);
  ASSERT_EQ(pair0.size(), 2u);
  ASSERT_EQ(pair1.size(), 2u);
  std::printf("[ RESULT ] bath first bending at 0 Hz: %.1f / %.1f rad/s; at 200 Hz spin: backward %.1f, forward %.1f\n",
              pair0[0], pair0[1], pair1[0], pair1[1]);
  EXPECT_LT(std::abs(pair0[1] - pair0[0]), 1.0);
  EXPECT_GT(pair1[1] - pair1[0], 10.0);
  EXPECT_LT(pair1[0], pair0[0]);
  EXPECT_GT(pair1[1], pair0[1]);
}

// The firmware's sampled controller (PidAxis per x/y, AxisTransform) holds the nonlinear
// plant at the centre with noise on: after 0.5 s the rotor is within a few gravity sags of
// the centre and has not drifted to the rings.
TEST(ClosedLoop, SampledFirmwareControllerLevitatesBothRigs) {
  for (const char* name : {"bath-amb-rig", "unicamp-amb-rig"}) {
    const auto board = test::board_from_repo(name);
    RotorAmbPlant plant(board.plant);
    plant.reset(true, 0.0);
    test::FirmwareControlLaw law(board, board.plant);
    PlantInputs in;
    in.amplifiers_enabled = true;
    const double dt = 1.0 / board.rate_hz;
    double worst = 0.0;
    const int n = static_cast<int>(0.5 / dt);
    for (int k = 0; k < n; ++k) {
      in.current_demand_a = law.demands_a(plant.outputs().displacement_m);
      plant.step(dt, in);
      if (k > n / 2) {
        const PlantTruth t = plant.truth();
        for (size_t b = 0; b < 2; ++b) worst = std::max(worst, std::hypot(t.amb_x_m[b], t.amb_y_m[b]));
      }
    }
    const double sag = plant.rotor_mass_kg() * board.plant.gravity_m_s2 / 2.0 /
                       (board.controller.kp_n_per_m - board.plant.amb[0].ks_n_per_m);
    std::printf("[ RESULT ] %s sampled PID at %.0f Hz: max radius at the AMBs over the last 0.25 s %.1f um (static sag %.1f um)\n",
                name, board.rate_hz, worst * 1e6, sag * 1e6);
    EXPECT_LT(worst, 3.0 * sag + 5e-6) << name;
  }
}

}  // namespace
}  // namespace amb::model::analysis
