// The loop's computation and transport delay (issue 38) in the sim backend and the SIL:
//  * the sim backend applies a fractional delay exactly for the zero-order hold (a plant that
//    integrates its demand, closed form);
//  * the board key is validated like the others;
//  * the sensitivity measured on the simulated rig (the firmware's PID and axis transform, the
//    nonlinear penalty-contact plant integrated by its own sub-stepping, a sine added to one
//    demand) agrees with the exact discrete analysis (matrix exponentials) at each delay.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "firmware/board/board.hpp"
#include "firmware/control/axis_transform.hpp"
#include "firmware/control/pid_axis.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "firmware/supervisory/register_addresses.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/sim/sim_rig.hpp"
#include "model/analysis/closed_loop.hpp"
#include "model/plant/rotor_amb_plant.hpp"
#include "tests/support/firmware_control_law.hpp"
#include "tests/support/test_paths.hpp"

using namespace amb;

namespace {

// x' = demand on axis 0 (an ideal integrator): x(t) is the integral of the held demand.
class IntegratorPlant final : public model::Plant {
 public:
  void reset(bool, double) override { x_ = 0.0; t_ = 0.0; }
  void step(double dt_s, const model::PlantInputs& in) override {
    x_ += dt_s * in.current_demand_a[0];
    t_ += dt_s;
    ++steps;
  }
  model::PlantOutputs outputs() const override {
    model::PlantOutputs o;
    o.t_s = t_;
    o.displacement_m[0] = x_;
    return o;
  }
  model::PlantTruth truth() const override { return {}; }
  void set_faults(const model::PlantFaults&) override {}
  int steps = 0;

 private:
  double x_ = 0.0, t_ = 0.0;
};

std::string board_text(const std::string& name) {
  std::ifstream f(std::string(test::source_dir()) + "/boards/" + name + ".toml");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Demands 1, 2, 3, ... written at t = 0, T, 2T, ...; with a delay of d periods the integral at
// 4T is sum over the held pieces. Closed form against the backend.
TEST(LoopDelay, SimBackendAppliesFractionalDelayExactly) {
  const int64_t period_ns = 100'000;
  for (double d : {0.0, 0.25, 0.5, 1.0, 1.75}) {
    auto plant = std::make_unique<IntegratorPlant>();
    IntegratorPlant* p = plant.get();
    hal::sim::SimRig rig(std::move(plant));
    rig.set_demand_delay_ns(std::llround(d * period_ns));
    for (int k = 0; k < 4; ++k) {
      hal::AnalogOutputs out{};
      out.current_demand_a[0] = k + 1.0;
      out.amplifiers_enabled = true;
      rig.analog().write(out);
      rig.clock().wait_until_ns((k + 1) * period_ns);
    }
    // Demand k+1 acts on [k T + d T, (k+1) T + d T) (the last one up to 4T).
    double expect = 0.0;
    for (int k = 0; k < 4; ++k) {
      const double from = (k + d) * 1e-4, to = std::min(4e-4, (k + 1 + d) * 1e-4);
      if (to > from) expect += (k + 1.0) * (to - from);
    }
    hal::AnalogInputs in;
    ASSERT_TRUE(rig.analog().read(in));
    const double x = p->outputs().displacement_m[0];
    std::printf("[ RESULT ] delay %.2f periods: integral %.6e (closed form %.6e), plant steps %d\n", d, x, expect, p->steps);
    EXPECT_NEAR(x, expect, 1e-12 * 4.0) << "delay " << d;
    EXPECT_EQ(rig.delay_overflows(), 0u);
  }
  EXPECT_THROW(hal::sim::SimRig(std::make_unique<IntegratorPlant>()).set_demand_delay_ns(-1), std::invalid_argument);
}

TEST(LoopDelay, BoardKeyIsValidated) {
  std::string text = board_text("bath-amb-rig");
  const size_t own = text.find("loop_delay_periods = 0.0");  // the reference board states it
  ASSERT_NE(own, std::string::npos);
  EXPECT_EQ(board::parse_board(text, "bath").loop_delay_periods, 0.0);
  text.erase(own, text.find('\n', own) + 1 - own);
  const std::string anchor = "rate_hz = 10000.0\n";
  const size_t at = text.find(anchor);
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(board::parse_board(text, "bath").loop_delay_periods, 0.0);  // absent: none
  for (const char* bad : {"-0.1", "2.5", "\"one\""}) {
    std::string t = text;
    t.insert(at + anchor.size(), std::string("loop_delay_periods = ") + bad + "\n");
    try {
      board::parse_board(t, "test.toml");
      ADD_FAILURE() << "accepted loop_delay_periods = " << bad;
    } catch (const board::BoardError& e) {
      std::printf("[ RESULT ] loop_delay_periods = %s: %s\n", bad, e.what());
      EXPECT_EQ(e.key(), "controller.loop_delay_periods");
    }
  }
  for (const char* bad_lead : {"lead_zero_hz = 300.0\nlead_pole_hz = 200.0\n", "lead_pole_hz = 200.0\n"}) {
    std::string t = text;
    t.insert(at + anchor.size(), bad_lead);
    try {
      board::parse_board(t, "test.toml");
      ADD_FAILURE() << "accepted " << bad_lead;
    } catch (const board::BoardError& e) {
      std::printf("[ RESULT ] lead keys: %s\n", e.what());
      EXPECT_NE(e.key().find("controller.lead_"), std::string::npos) << e.key();
    }
  }
  text.insert(at + anchor.size(), "loop_delay_periods = 0.75\n");
  EXPECT_DOUBLE_EQ(board::parse_board(text, "test.toml").loop_delay_periods, 0.75);
}

// The firmware's controller (PidAxis per direction, AxisTransform) on the sim backend with the
// delay, no noise, levitated start; a sine of `amp_a` is added to demand `axis`; S = U / D at
// the sine's frequency (one-bin DFT over whole cycles after the transient).
std::complex<double> measured_sensitivity(const board::BoardConfig& b, double delay_periods, int axis, double f_hz,
                                          double amp_a) {
  model::PlantParams pp = b.plant;
  for (auto& s : pp.sensor) s.noise_rms_m = 0.0;
  auto plant = std::make_unique<model::RotorAmbPlant>(pp);
  plant->reset(true, 0.0);
  hal::sim::SimRig rig(std::move(plant));
  const int64_t period_ns = std::llround(1e9 / b.rate_hz);
  rig.set_demand_delay_ns(std::llround(delay_periods * period_ns));
  test::FirmwareControlLaw law(b, pp);
  const double t_s = 1.0 / b.rate_hz;
  const int settle = static_cast<int>(0.3 * b.rate_hz);
  const int n = static_cast<int>(std::lround(std::round(40.0 * 1.0) / (f_hz * t_s)));  // ~40 cycles
  std::complex<double> su = 0.0, sd = 0.0;
  double mean_u = 0.0;
  std::vector<double> u_rec, d_rec;
  for (int k = 0; k < settle + n; ++k) {
    hal::AnalogInputs in;
    rig.analog().read(in);
    hal::AnalogOutputs out{};
    out.amplifiers_enabled = true;
    out.current_demand_a = law.demands_a(in.displacement_m);
    const double dk = amp_a * std::sin(2.0 * M_PI * f_hz * k * t_s);
    out.current_demand_a[static_cast<size_t>(axis)] += dk;
    if (k >= settle) {
      u_rec.push_back(out.current_demand_a[static_cast<size_t>(axis)]);
      d_rec.push_back(dk);
      mean_u += out.current_demand_a[static_cast<size_t>(axis)];
    }
    rig.analog().write(out);
    rig.clock().wait_until_ns((k + 1) * period_ns);
  }
  mean_u /= n;
  for (int i = 0; i < n; ++i) {
    const std::complex<double> w = std::exp(std::complex<double>(0.0, -2.0 * M_PI * f_hz * (settle + i) * t_s));
    su += (u_rec[static_cast<size_t>(i)] - mean_u) * w;
    sd += d_rec[static_cast<size_t>(i)] * w;
  }
  return su / sd;
}

// Bath rig, injection on A1 at the one-period peak (176 Hz), below and above it, delays 0, 0.5,
// 1, and the variant tuned for one period (its lead and notch in the firmware's PidAxis):
// |S| from the simulated rig within 5 % of the analysis (the acceptance band). The
// plant (symplectic Euler sub-steps, nonlinear force law about the sag) and the analysis (exact
// discretisation of the linearised rig) share only the board file.
TEST(LoopDelay, SensitivityMeasuredInSilMatchesAnalysis) {
  const board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig.toml");
  const board::BoardConfig t = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig-delay1.toml");
  struct Case {
    const board::BoardConfig* board;
    double delay;
  };
  for (const Case& c : {Case{&b, 0.0}, Case{&b, 0.5}, Case{&b, 1.0}, Case{&t, 1.0}}) {
    model::analysis::ClosedLoopOptions o;
    o.sample_rate_hz = c.board->rate_hz;
    o.loop_delay_periods = c.delay;
    const model::analysis::ClosedLoopModel cl(c.board->plant, c.board->controller, o);
    for (double f : {120.0, 176.0, 260.0}) {
      const double model_s = std::abs(cl.sensitivity(0, f));
      const double sil_s = std::abs(measured_sensitivity(*c.board, c.delay, 0, f, 0.02));
      std::printf("[ RESULT ] %s delay %.1f periods, %.0f Hz: |S| SIL %.3f, analysis %.3f (%+.1f %%)\n",
                  c.board->name.c_str(), c.delay, f, sil_s, model_s, 100.0 * (sil_s / model_s - 1.0));
      EXPECT_NEAR(sil_s, model_s, 0.05 * model_s) << c.board->name << " delay " << c.delay << " f " << f;
    }
  }
}

// The firmware (supervisor, loop runner) in SIL with a board's delay: levitate from the
// touchdown bearings, spin to the operating speed, hold 0.5 s; the orbit stays well inside the
// clearance and the loop never leaves `running`. The reference board at one period (zone D in
// the analysis, still stable) and the variant tuned for it (zone A).
struct DelayRun {
  bool levitated = false, at_speed = false;
  double orbit_max_m = 0.0, clearance_m = 0.0, demand_rms_a = 0.0;
  fw::State end = fw::State::unconfigured;
};

DelayRun levitate_with_delay(board::BoardConfig b) {
  sil::SilRig rig(b);
  fw::Supervisor& sup = rig.supervisor();
  DelayRun r;
  r.clearance_m = std::min(b.plant.aux[0].clearance_m, b.plant.aux[1].clearance_m);
  rig.run_for(0.02);
  sup.post(fw::Command::levitate);
  auto at = [](fw::Phase p) { return [p](const fw::Status& s) { return s.phase == p || s.state == fw::State::fault; }; };
  r.levitated = rig.run_until(at(fw::Phase::levitated), 5.0) && sup.state() == fw::State::levitating;
  if (!r.levitated) return r;
  sup.post(fw::Command::run);
  r.at_speed = rig.run_until(at(fw::Phase::at_speed), 30.0) && sup.state() == fw::State::running;
  if (!r.at_speed) return r;
  rig.run_for(0.1);
  const double end = rig.time_s() + 0.5;
  double sum = 0.0, mean = 0.0;
  int n = 0;
  std::vector<double> d;
  while (rig.time_s() < end) {
    rig.run_for(1.0 / b.rate_hz);
    const fw::Status s = sup.status();
    r.orbit_max_m = std::max({r.orbit_max_m, s.orbit_radius_m[0], s.orbit_radius_m[1]});
    d.push_back(s.current_demand_a[0]);
    mean += s.current_demand_a[0];
    ++n;
  }
  mean /= n;
  for (double v : d) sum += (v - mean) * (v - mean);
  r.demand_rms_a = std::sqrt(sum / n);
  r.end = sup.state();
  return r;
}

TEST(LoopDelay, DelayedBoardsLevitateAndSpinInSil) {
  board::BoardConfig ref = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig.toml");
  ref.loop_delay_periods = 1.0;
  const board::BoardConfig tuned = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig-delay1.toml");
  EXPECT_EQ(tuned.loop_delay_periods, 1.0);
  for (const board::BoardConfig* b : std::array<const board::BoardConfig*, 2>{&ref, &tuned}) {
    const DelayRun r = levitate_with_delay(*b);
    std::printf("[ RESULT ] %s, delay %.2f periods: levitated %d, at speed %d, steady orbit max %.1f um (clearance %.0f um), "
                "demand A1 ac rms %.3f A\n", b->name.c_str(), b->loop_delay_periods, r.levitated, r.at_speed,
                r.orbit_max_m * 1e6, r.clearance_m * 1e6, r.demand_rms_a);
    ASSERT_TRUE(r.levitated) << b->name;
    ASSERT_TRUE(r.at_speed) << b->name;
    EXPECT_LT(r.orbit_max_m, 0.1 * r.clearance_m) << b->name;
    EXPECT_EQ(r.end, fw::State::running) << b->name;
  }
}

// A stamp clock that moves 1 us at every read: each period reads it four times (woke, sample
// in, step done, demand written), so the loop's delay is exactly 3 us and each part 1 us.
class TickingClock final : public hal::Clock {
 public:
  int64_t now_ns() override { return t_ += 1000; }
  int64_t wait_until_ns(int64_t d) override { return t_ = std::max(t_, d); }

 private:
  int64_t t_ = 0;
};

// The per-period stamps land in the loop statistics and on the supervisory link (0x0410..).
TEST(LoopDelay, LoopStampsAreServedOnTheSupervisoryLink) {
  const board::BoardConfig b = board::load_board(std::string(test::source_dir()) + "/boards/bath-amb-rig.toml");
  hal::sim::SimRig sim(std::make_unique<IntegratorPlant>());
  fw::Supervisor sup;
  sup.configure(b);
  fw::LoopRunner loop(sim.clock(), sim.analog(), sim.discrete(), sup);
  TickingClock tick;
  loop.set_stamp_clock(&tick);
  loop.run_periods(1000);
  const fw::LoopStats& ls = loop.stats();
  EXPECT_EQ(ls.periods, 1000u);
  EXPECT_EQ(ls.max_delay_ns, 3000);
  EXPECT_EQ(ls.delay_quantile_ns(0.5), 3000);
  EXPECT_EQ(ls.delay_quantile_ns(0.999), 3000);
  EXPECT_EQ(ls.max_read_ns, 1000);
  EXPECT_EQ(ls.max_step_ns, 1000);
  EXPECT_EQ(ls.max_write_ns, 1000);
  fw::RegisterSources src;
  src.loop_stats = [&] { return ls; };
  fw::RegisterMap map(std::move(src));
  std::array<uint16_t, 16> r{};
  ASSERT_EQ(map.read_registers(fw::regs::loop_delay_ns, r), hal::RegisterHandler::ok);
  auto u32 = [&](size_t i) { return static_cast<uint32_t>(r[2 * i]) << 16 | r[2 * i + 1]; };
  EXPECT_EQ(u32(0), 3000u);  // p50
  EXPECT_EQ(u32(1), 3000u);  // p99
  EXPECT_EQ(u32(3), 3000u);  // max
  EXPECT_EQ(u32(4), 3000u);  // mean
  EXPECT_EQ(u32(5), 1000u);  // read
  EXPECT_EQ(u32(6), 1000u);  // step
  EXPECT_EQ(u32(7), 1000u);  // write
  // The SIL's own stamps: the host's work, nonzero, ordered quantiles.
  sil::SilRig rig(b);
  rig.run_for(0.2);
  const fw::LoopStats& s = rig.loop().stats();
  std::printf("[ RESULT ] SIL host work, sample -> demand written: p50 %.2f us, p99 %.2f us, p99.9 %.2f us, max %.2f us "
              "(%llu periods)\n", s.delay_quantile_ns(0.5) * 1e-3, s.delay_quantile_ns(0.99) * 1e-3,
              s.delay_quantile_ns(0.999) * 1e-3, s.max_delay_ns * 1e-3, static_cast<unsigned long long>(s.periods));
  EXPECT_GT(s.max_delay_ns, 0);
  EXPECT_LE(s.delay_quantile_ns(0.5), s.delay_quantile_ns(0.99));
  EXPECT_LE(s.delay_quantile_ns(0.99), s.max_delay_ns);
}

}  // namespace
