// amb-step-cost: a fixed number of control steps (Supervisor::step, Bath rig, 10 kHz) in one
// case, for an instruction count under callgrind (scripts/step-cost.sh). Instruction counts do
// not depend on the machine's load, so they settle what amb-bench's medians cannot on a shared
// machine. The timed part is measured_steps(); the set-up before it is not counted.
//
//   amb-step-cost start|levitated|sweep [STEPS]
//     start      as amb-bench BM_ControlStep: levitate posted, the steps from lift-off on
//     levitated  as BM_ControlStepLevitated: the steps after the rotor is levitated
//     sweep      as BM_ControlStepSweep: levitated, the sweep generator recording axis 0 for
//                every measured step (refused when STEPS exceeds what axis 0 records)
// STEPS default 20000. Prints one JSON line (case, steps, phase and sweep state after) on
// stdout; exit 0 ok, 1 bad input, 2 when the case did not hold for every measured step.
//
// Uses only the Supervisor API that predates the sweep generator (configure, post, step,
// status) for start and levitated, so the same file builds against an older tree for a
// before/after count (docs/sweep.md "Cost in the loop").
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "firmware/app/supervisor.hpp"
#include "firmware/board/board.hpp"

#if __has_include("firmware/sweep/sweep_generator.hpp")
#define AMB_STEP_COST_HAVE_SWEEP 1
#else
#define AMB_STEP_COST_HAVE_SWEEP 0
#endif

namespace {

using namespace amb;

struct StepRig {
  fw::Supervisor sup;
  hal::AnalogInputs in{};
  hal::DiscreteInputs din{};
  hal::AnalogOutputs out{};
  hal::DiscreteOutputs dout{};
  long k = 0;
  void step() {
    in.t_ns += 100000;
    sup.step(in, true, din, out, dout);
  }
};

// The counted part (callgrind --toggle-collect): the same body as amb-bench's timed loop.
__attribute__((noinline)) void measured_steps(StepRig& r, long steps) {
  for (long i = 0; i < steps; ++i) {
    r.in.displacement_m[0] = 1e-6 * std::sin(0.01 * static_cast<double>(++r.k));
    r.step();
    asm volatile("" : : "r"(&r.out) : "memory");
  }
}

int usage(const char* why) {
  std::fprintf(stderr, "amb-step-cost: %s\nusage: amb-step-cost start|levitated|sweep [STEPS]\n", why);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) return usage("expected a case and an optional step count");
  const std::string which = argv[1];
  if (which != "start" && which != "levitated" && which != "sweep")
    return usage(("unknown case '" + which + "' (start, levitated, sweep)").c_str());
  long steps = 20000;
  if (argc == 3) {
    char* end = nullptr;
    steps = std::strtol(argv[2], &end, 10);
    if (end == argv[2] || *end != '\0' || steps < 1 || steps > 100000000)
      return usage(("STEPS '" + std::string(argv[2]) + "' is not an integer in [1, 100000000]").c_str());
  }
#if !AMB_STEP_COST_HAVE_SWEEP
  if (which == "sweep") return usage("case 'sweep': this tree has no sweep generator");
#endif

  const board::BoardConfig b = board::load_board("bath-amb-rig");
  StepRig r;
  r.sup.configure(b);
  r.sup.post(fw::Command::levitate);
  if (which == "start") {
    r.sup.step(r.in, true, r.din, r.out, r.dout);
  } else {
    const int to_levitated = static_cast<int>((b.lifecycle.liftoff_ramp_s + b.lifecycle.settle_s) * b.rate_hz) + 20;
    for (int i = 0; i < to_levitated; ++i) r.step();
    if (r.sup.status().phase != fw::Phase::levitated) {
      std::fprintf(stderr, "amb-step-cost: not levitated after %d steps\n", to_levitated);
      return 2;
    }
  }
#if AMB_STEP_COST_HAVE_SWEEP
  uint32_t recorded_before = 0;
  if (which == "sweep") {
    // Default plan of the board; skip the settle periods so every measured step records.
    const fw::SweepParams& p = r.sup.sweep().params();
    const long settle = static_cast<long>(p.settle_periods) * p.samples_per_period;
    const long recordable = static_cast<long>(p.recorded_periods) * p.samples_per_period;
    if (steps > recordable)
      return usage(("case 'sweep': STEPS " + std::to_string(steps) + " exceeds the " +
                    std::to_string(recordable) + " steps axis 0 records").c_str());
    r.sup.request_sweep_start();
    for (long i = 0; i < settle + 1; ++i) r.step();
    const fw::SweepStatus s = r.sup.status().sweep;
    if (s.state != fw::SweepState::recording || s.axis != 0) {
      std::fprintf(stderr, "amb-step-cost: the sweep is not recording axis 0 (state %s)\n", fw::to_string(s.state));
      return 2;
    }
    recorded_before = s.period;
  }
#endif

  measured_steps(r, steps);

  const fw::Status st = r.sup.status();
  const char* sweep_state = "none";
  bool held = true;
  if (which == "levitated") held = st.phase == fw::Phase::levitated;
#if AMB_STEP_COST_HAVE_SWEEP
  sweep_state = fw::to_string(st.sweep.state);
  if (which == "levitated") held = held && st.sweep.state == fw::SweepState::idle;
  if (which == "sweep")
    held = st.phase == fw::Phase::levitated && st.sweep.state == fw::SweepState::recording &&
           st.sweep.axis == 0 && st.sweep.period >= recorded_before;
#endif
  std::printf("{\"case\":\"%s\",\"steps\":%ld,\"phase\":\"%s\",\"sweep\":\"%s\",\"held\":%s}\n", which.c_str(), steps,
              fw::to_string(st.phase), sweep_state, held ? "true" : "false");
  if (!held) {
    std::fprintf(stderr, "amb-step-cost: case '%s' did not hold to the last measured step\n", which.c_str());
    return 2;
  }
  return 0;
}
