// amb-host sweep: run a loop-sensitivity sweep (ISO 14839-3) on a board and bring its `sweep`
// event home: on a board file's simulated rig (--board: the firmware in the loop) or on a
// connected board over Modbus TCP (--connect: arm with the board's key, start, poll progress,
// download), or read a stored one (--event). Writes the event into --out, analyses it on the
// board's model (host-tools/core/sweep/sweep_analysis.hpp: S, T, G with coherence and band, the
// ISO 14839-3 zone per axis, the model beside it, the residual loop) and writes the HTML page.
// Progress goes to stderr. docs/sweep.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/report/sweep_page.hpp"
#include "host-tools/core/sweep/sweep_acquire.hpp"
#include "host-tools/core/sweep/sweep_analysis.hpp"
#include "host-tools/core/sweep/sweep_event.hpp"
#include "host-tools/core/ui/progress_lines.hpp"

namespace {

namespace sw = amb::host::sweep;

struct Args {
  std::string board;      ///< SIL: board name or file
  std::string connect;    ///< Modbus: board address
  std::string event;      ///< a stored sweep event to analyse (no acquisition)
  std::string model;      ///< board the analysis models (default: --board, else the event's board)
  std::string html;       ///< page path (default: the event's path with .html)
  bool no_residual = false;
  int port = 502;
  int unit = 1;
  std::string arm_key;    ///< decimal or 0x hex; default AMB_ARM_KEY
  std::string out_dir = "amb-out";
  double timeout_s = 900.0;
  bool spin = false;
  bool json = false;
  bool quiet = false;
};

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

/// The board the analysis models: --model, else --board, else the board the event names.
amb::board::BoardConfig model_board(const Args& a, const std::optional<amb::board::BoardConfig>& model, const sw::SweepRecord& r) {
  if (model) return *model;
  if (!a.board.empty()) return amb::board::load_board(a.board);
  try {
    return amb::board::load_board(r.board_name);
  } catch (const std::exception& e) {
    throw std::invalid_argument("the sweep names board '" + r.board_name + "', which is not an embedded board (" + e.what() +
                                "): give --model FILE");
  }
}

nlohmann::json acquisition_json(const Args& a, const sw::AcquireResult& res) {
  const sw::SweepRecord& r = res.record;
  nlohmann::json axes = nlohmann::json::array();
  for (const sw::SweepAxisRecord& x : r.axes) {
    const AxisLook l = quick_look(r, x);
    axes.push_back({{"axis", l.axis}, {"samples", l.samples}, {"u_over_e_peak", l.peak_ratio}, {"u_over_e_peak_hz", l.peak_hz}});
  }
  const double f_lo = r.plan.frequencies_hz.empty() ? 0.0 : r.plan.frequencies_hz.front();
  const double f_hi = r.plan.frequencies_hz.empty() ? 0.0 : r.plan.frequencies_hz.back();
  return {{"board", r.board_name},
          {"rig", r.rig_name},
          {"event", res.event_path},
          {"event_bytes", res.event_bytes},
          {"acquired", a.event.empty()},
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
}

void print_text(const nlohmann::json& j, const sw::SweepAnalysis* an, const std::string& page) {
  std::printf("sweep %s (%s): %zu axes, %zu lines %.4g .. %.4g Hz (N %u, %u settle + %u recorded periods), "
              "amplitude %.4g A (%.3g x bias), crest factor %.3f%s%s\n",
              j["board"].get<std::string>().c_str(), j["event"].get<std::string>().c_str(), j["axes"].size(),
              j["lines"].get<size_t>(), j["f_first_hz"].get<double>(), j["f_last_hz"].get<double>(),
              j["samples_per_period"].get<unsigned>(), j["settle_periods"].get<unsigned>(), j["recorded_periods"].get<unsigned>(),
              j["amplitude_a"].get<double>(),
              j["bias_current_a"].get<double>() > 0 ? j["amplitude_a"].get<double>() / j["bias_current_a"].get<double>() : 0.0,
              j["crest_factor"].get<double>(), j["aborted"].get<bool>() ? ", ABORTED: " : "",
              j["aborted"].get<bool>() ? j["abort_reason"].get<std::string>().c_str() : "");
  if (an == nullptr) return;
  std::printf("ISO 14839-3 zone per axis (zone, peak of |S| [95 %% band]; the board's model):\n");
  for (const sw::ZoneRow& z : an->zones)
    std::printf("  %s: %s; model %.3f at %.4g Hz, zone %s (%+.1f %%)\n", z.axis_name.c_str(),
                z.measured.found ? z.measured.statement.c_str() : "no line above the coherence floor", z.model_peak,
                z.model_peak_hz, z.model_zone.c_str(), z.peak_error_pct);
  std::printf("measured vs model: S %.2f dB rms, G %.2f dB rms\n", an->s_db_rms, an->g_db_rms);
  if (an->residual_done) std::printf("residual loop: %s\n", an->residual.verdict.c_str());
  for (const std::string& n : an->notes) std::printf("note: %s\n", n.c_str());
  if (!page.empty()) std::printf("page: %s\n", page.c_str());
}

int run(const Args& a) {
  std::optional<amb::board::BoardConfig> model;  // read first: a bad --model is named before anything runs
  if (!a.model.empty()) model = amb::board::load_board(a.model);
  const int sources = static_cast<int>(!a.board.empty()) + static_cast<int>(!a.connect.empty()) + static_cast<int>(!a.event.empty());
  if (sources != 1)
    throw std::invalid_argument("give exactly one of --board FILE|NAME (simulated rig), --connect HOST (board over Modbus) "
                                "and --event FILE (a stored sweep event)");
  sw::AcquireResult res;
  if (!a.event.empty()) {
    res.record = sw::read_sweep_event_file(a.event);
    res.event_path = a.event;
    res.event_bytes = std::filesystem::file_size(a.event);
  } else {
    sw::AcquireOptions o;
    o.out_dir = a.out_dir;
    o.timeout_s = a.timeout_s;
    o.spin = a.spin;
    if (!a.quiet) o.progress = amb::host::ui::periodic_lines("sweep");
    try {
      if (!a.board.empty()) {
        res = sw::acquire_sweep_sil(amb::board::load_board(a.board), o);
      } else {
        amb::host::link::LinkOptions lo;
        lo.host = a.connect;
        lo.port = a.port;
        lo.unit_id = a.unit;
        res = sw::acquire_sweep_modbus(lo, amb::host::cli::arm_key(a.arm_key, "", "--connect needs the board's arm key: --arm-key KEY or AMB_ARM_KEY"), o);
      }
    } catch (const sw::AcquireError& e) {
      std::fprintf(stderr, "amb-host sweep: error: %s\n", e.what());
      return 2;
    }
  }
  nlohmann::json j = acquisition_json(a, res);
  std::unique_ptr<sw::SweepAnalysis> an;
  std::string page;
  if (!res.record.axes.empty()) {
    const amb::board::BoardConfig b = model_board(a, model, res.record);
    if (!a.quiet) std::fprintf(stderr, "sweep: analysing %zu axes on the model of %s%s\n", res.record.axes.size(), b.name.c_str(),
                               a.no_residual ? "" : " (with the residual loop)");
    sw::SweepAnalysisOptions ao;
    ao.run_residual = !a.no_residual;
    try {
      an = std::make_unique<sw::SweepAnalysis>(sw::analyse_sweep(res.record, b, ao));
    } catch (const std::invalid_argument& e) {  // a record the analysis cannot read: the event is named
      throw std::invalid_argument(res.event_path + ": " + e.what());
    }
    j["analysis"] = sw::sweep_analysis_json(*an);
    std::filesystem::path p = a.html.empty() ? std::filesystem::path(res.event_path).replace_extension(".html")
                                             : std::filesystem::path(a.html);
    page = amb::host::report::write_sweep_page(*an, p.string());
    j["page"] = page;
    if (!a.quiet) std::fprintf(stderr, "sweep: page %s\n", page.c_str());
  }
  if (a.json) std::printf("%s\n", j.dump(2).c_str());
  else print_text(j, an.get(), page);
  return res.record.aborted ? 2 : 0;
}

void declare(CLI::App& sub, Args& a) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("--board", a.board, "board name or file: sweep its simulated rig (SIL)"), "board");
  sub.add_option("--connect", a.connect, "board address: sweep the board over Modbus TCP");
  hc::input_file(sub.add_option("--event", a.event, "analyse a stored sweep event (AMBE v4) instead of running one"), "ambe");
  hc::input_file(sub.add_option("--model", a.model, "board the analysis models (default: --board, else the board the event names)"),
                 "board");
  hc::whole(sub.add_option("--port", a.port, "Modbus TCP port (with --connect)"), 1, 65535);
  hc::whole(sub.add_option("--unit", a.unit, "Modbus unit id (with --connect)"), 0, 255);
  sub.add_option("--arm-key", a.arm_key, "the board's arm key (with --connect; decimal or 0x hex; default AMB_ARM_KEY)");
  hc::output_path(sub.add_option("--out", a.out_dir, "directory for the sweep event")->capture_default_str());
  hc::output_path(sub.add_option("--html", a.html, "the sweep page (default: the event's path with .html)"));
  hc::positive(sub.add_option("--timeout", a.timeout_s, "time allowed for the sweep, s (simulated with --board)"), 1e5, "s");
  sub.add_flag("--spin", a.spin, "SIL: sweep at the operating speed instead of levitated at rest");
  sub.add_flag("--no-residual", a.no_residual, "estimate and compare with the model only (no residual loop)");
  sub.add_flag("--json", a.json, "print the sweep and its analysis as JSON");
  sub.add_flag("--quiet", a.quiet, "no progress lines on stderr");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "sweep", "run a loop-sensitivity sweep (ISO 14839-3) on a board or its simulated rig, download its event and rate the loop",
    declare, run);

}  // namespace
