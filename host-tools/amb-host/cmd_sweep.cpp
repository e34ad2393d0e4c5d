// amb-host sweep: run a loop-sensitivity sweep (ISO 14839-3) on a board and bring its `sweep`
// event home: on a board file's simulated rig (--board: the firmware in the loop) or on a
// connected board over Modbus TCP (--connect: arm with the board's key, start, poll progress,
// download). Writes the event into --out and prints the record's summary (axes, lines,
// amplitude, crest factor, aborted?). Progress goes to stderr. Board side: docs/sweep.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/sweep/sweep_acquire.hpp"
#include "host-tools/core/ui/progress_lines.hpp"

namespace {

namespace sw = amb::host::sweep;

struct Args {
  std::string board;      ///< SIL: board name or file
  std::string connect;    ///< Modbus: board address
  int port = 502;
  int unit = 1;
  std::string arm_key;    ///< decimal or 0x hex; default AMB_ARM_KEY
  std::string out_dir = "amb-out";
  double timeout_s = 900.0;
  bool spin = false;
  bool json = false;
  bool quiet = false;
};

uint32_t arm_key_of(const Args& a) {
  auto parse = [](const std::string& text, const char* from) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 0);
    if (text.empty() || *end != '\0' || v == 0 || v > 0xFFFFFFFFull)
      throw std::invalid_argument(std::string("arm key from ") + from + " must be an integer in [1, 2^32-1], got '" + text + "'");
    return static_cast<uint32_t>(v);
  };
  if (!a.arm_key.empty()) return parse(a.arm_key, "--arm-key");
  if (const char* env = std::getenv("AMB_ARM_KEY"); env && *env) return parse(env, "AMB_ARM_KEY");
  throw std::invalid_argument("--connect needs the board's arm key: --arm-key KEY or AMB_ARM_KEY");
}

/// The figures of a record: per axis u/e at the excited lines (one-bin DFT averaged over the
/// recorded periods) and its peak -- a quick look; the estimators are the analysis's.
struct AxisLook {
  int axis = 0;
  size_t samples = 0;
  double peak_ratio = 0.0, peak_hz = 0.0;
};
AxisLook quick_look(const sw::SweepRecord& r, const sw::SweepAxisRecord& a) {
  AxisLook l;
  l.axis = a.axis;
  l.samples = a.excitation_a.size();
  const size_t n = r.plan.samples_per_period;
  for (double f : r.plan.frequencies_hz) {
    double er = 0, ei = 0, ur = 0, ui = 0;
    const double w = 2.0 * 3.14159265358979323846 * f / r.rate_hz;
    for (size_t k = 0; k < a.excitation_a.size(); ++k) {
      const double c = std::cos(w * static_cast<double>(k % n)), s = std::sin(w * static_cast<double>(k % n));
      er += a.excitation_a[k] * c;
      ei -= a.excitation_a[k] * s;
      ur += a.summing_point_a[k] * c;
      ui -= a.summing_point_a[k] * s;
    }
    const double ratio = std::hypot(ur, ui) / std::max(1e-300, std::hypot(er, ei));
    if (ratio > l.peak_ratio) {
      l.peak_ratio = ratio;
      l.peak_hz = f;
    }
  }
  return l;
}

int run(const Args& a) {
  if (a.board.empty() == a.connect.empty())
    throw std::invalid_argument("give exactly one of --board FILE|NAME (simulated rig) and --connect HOST (board over Modbus)");
  sw::AcquireOptions o;
  o.out_dir = a.out_dir;
  o.timeout_s = a.timeout_s;
  o.spin = a.spin;
  if (!a.quiet) o.progress = amb::host::ui::periodic_lines("sweep");
  sw::AcquireResult res;
  try {
    if (!a.board.empty()) {
      const amb::board::BoardConfig b = amb::board::load_board(a.board);
      res = sw::acquire_sweep_sil(b, o);
    } else {
      amb::host::link::LinkOptions lo;
      lo.host = a.connect;
      lo.port = a.port;
      lo.unit_id = a.unit;
      const uint32_t key = arm_key_of(a);
      res = sw::acquire_sweep_modbus(lo, key, o);
    }
  } catch (const sw::AcquireError& e) {
    std::fprintf(stderr, "amb-host sweep: error: %s\n", e.what());
    return 2;
  }
  const sw::SweepRecord& r = res.record;
  nlohmann::json axes = nlohmann::json::array();
  for (const sw::SweepAxisRecord& x : r.axes) {
    const AxisLook l = quick_look(r, x);
    axes.push_back({{"axis", l.axis}, {"samples", l.samples}, {"u_over_e_peak", l.peak_ratio}, {"u_over_e_peak_hz", l.peak_hz}});
  }
  const double f_lo = r.plan.frequencies_hz.empty() ? 0.0 : r.plan.frequencies_hz.front();
  const double f_hi = r.plan.frequencies_hz.empty() ? 0.0 : r.plan.frequencies_hz.back();
  nlohmann::json j{{"board", r.board_name},
                   {"rig", r.rig_name},
                   {"event", res.event_path},
                   {"event_bytes", res.event_bytes},
                   {"rate_hz", r.rate_hz},
                   {"speed_hz", r.speed_hz},
                   {"injection", "controller_output"},
                   {"excitation", r.plan.kind == sw::ExcitationKind::multisine ? "multisine" : "stepped_sine"},
                   {"lines", r.plan.frequencies_hz.size()},
                   {"f_first_hz", f_lo},
                   {"f_last_hz", f_hi},
                   {"samples_per_period", r.plan.samples_per_period},
                   {"settle_periods", r.plan.settle_periods},
                   {"recorded_periods", r.plan.recorded_periods},
                   {"amplitude_a", r.plan.amplitude_a},
                   {"bias_current_a", r.bias_current_a},
                   {"crest_factor", r.plan.crest_factor},
                   {"aborted", r.aborted},
                   {"abort_reason", r.abort_reason},
                   {"refusals", res.refusals},
                   {"aborts", res.aborts},
                   {"axes", axes}};
  if (a.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("sweep %s (%s): %zu axes, %zu lines %.4g .. %.4g Hz (N %u, %u settle + %u recorded periods), "
                "amplitude %.4g A (%.3g x bias), crest factor %.3f%s%s\n",
                r.board_name.c_str(), res.event_path.c_str(), r.axes.size(), r.plan.frequencies_hz.size(), f_lo, f_hi,
                r.plan.samples_per_period, r.plan.settle_periods, r.plan.recorded_periods, r.plan.amplitude_a,
                r.bias_current_a > 0 ? r.plan.amplitude_a / r.bias_current_a : 0.0, r.plan.crest_factor,
                r.aborted ? ", ABORTED: " : "", r.aborted ? r.abort_reason.c_str() : "");
    for (const auto& x : axes)
      std::printf("  axis %d: %zu samples, u/e peak %.3f at %.4g Hz\n", x["axis"].get<int>(), x["samples"].get<size_t>(),
                  x["u_over_e_peak"].get<double>(), x["u_over_e_peak_hz"].get<double>());
  }
  return r.aborted ? 2 : 0;
}

const amb::host::Registration reg{
    "sweep", "run a loop-sensitivity sweep (ISO 14839-3) on a board or its simulated rig and download its event",
    [](CLI::App& sub, std::function<int()>& run_fn) {
      auto a = std::make_shared<Args>();
      namespace hc = amb::host::cli;
      hc::input_file(sub.add_option("--board", a->board, "board name or file: sweep its simulated rig (SIL)"), "board");
      sub.add_option("--connect", a->connect, "board address: sweep the board over Modbus TCP");
      hc::whole(sub.add_option("--port", a->port, "Modbus TCP port (with --connect)"), 1, 65535);
      hc::whole(sub.add_option("--unit", a->unit, "Modbus unit id (with --connect)"), 0, 255);
      sub.add_option("--arm-key", a->arm_key, "the board's arm key (with --connect; decimal or 0x hex; default AMB_ARM_KEY)");
      hc::output_path(sub.add_option("--out", a->out_dir, "directory for the sweep event")->capture_default_str());
      hc::positive(sub.add_option("--timeout", a->timeout_s, "time allowed for the sweep, s (simulated with --board)"), 1e5, "s");
      sub.add_flag("--spin", a->spin, "SIL: sweep at the operating speed instead of levitated at rest");
      sub.add_flag("--json", a->json, "print the record's summary as JSON");
      sub.add_flag("--quiet", a->quiet, "no progress lines on stderr");
      run_fn = [a] { return run(*a); };
    }};

}  // namespace
