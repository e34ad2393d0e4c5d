// amb-host bearing-check: envelope analysis of a measured record against a bearing's defect
// frequencies. Logic: host-tools/core/bearing/bearing_check.hpp.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/bearing/bearing_check.hpp"
#include "host-tools/core/io/mat_file.hpp"
#include "model/bearing/catalogue.hpp"
#include "model/bearing/geometry.hpp"

namespace {

struct Args {
  std::string mat_file;
  std::string var;
  double fs_hz = 0.0;
  double rpm = 0.0;
  std::string bearing;
  bool json = false;
  bool remove_discrete = false;
};

nlohmann::json opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string known_bearings() {
  std::string known;
  for (const auto& g : amb::model::bearing::bearing_catalogue()) known += (known.empty() ? "" : ", ") + std::string(g.name);
  return known;
}

int bad_input(const std::string& what) {
  std::fprintf(stderr, "amb-host bearing-check: error: %s\n", what.c_str());
  return 1;
}

int run(const Args& a) {
  namespace mb = amb::model::bearing;
  namespace hb = amb::host::bearing;
  // --fs and --rpm are finite and in range (checked at parse); the bearing is in the catalogue.
  const auto geometry = mb::find_bearing(a.bearing);
  if (!geometry) return bad_input("--bearing: unknown bearing '" + a.bearing + "' (known: " + known_bearings() + ")");
  std::vector<double> x;
  try {
    x = amb::host::read_mat_vector(a.mat_file, a.var);
  } catch (const std::exception& e) {
    return bad_input("--mat '" + a.mat_file + "' --var '" + a.var + "': " + e.what());
  }
  // Where the record cannot hold the defect lines, say so instead of giving a verdict: every
  // line examined must lie below the Nyquist frequency, and the record must span enough
  // revolutions of the cage (the slowest line) to resolve it.
  const int harmonics = hb::BearingCheckOptions{}.harmonics;
  const mb::DefectFrequencies defect = mb::defect_frequencies(*geometry, a.rpm / 60.0);
  const double highest_hz = harmonics * defect.bpfi_hz + 3.0 * defect.shaft_hz;
  if (highest_hz >= 0.5 * a.fs_hz)
    return bad_input("--rpm " + num(a.rpm) + " with --fs " + num(a.fs_hz) + ": the defect lines examined reach " +
                     num(highest_hz) + " Hz (" + std::to_string(harmonics) +
                     " x BPFI + 3 x shaft), above the Nyquist frequency " + num(0.5 * a.fs_hz) +
                     " Hz; nothing can be analysed (check --rpm and --fs)");
  const double duration_s = static_cast<double>(x.size()) / a.fs_hz;
  if (duration_s * defect.ftf_hz < 10.0)
    return bad_input("--rpm " + num(a.rpm) + " with --fs " + num(a.fs_hz) + ": the record (" +
                     std::to_string(x.size()) + " samples, " + num(duration_s) + " s) spans " +
                     num(duration_s * defect.ftf_hz) + " cage revolutions; at least 10 are needed to resolve the lines "
                     "(check --rpm and --fs)");
  hb::BearingCheckResult r;
  try {
    hb::BearingCheckOptions o;
    o.remove_discrete = a.remove_discrete;
    r = hb::check_bearing(x, a.fs_hz, a.rpm / 60.0, *geometry, o);
  } catch (const std::invalid_argument& e) {
    return bad_input(e.what());
  }
  const auto& p = r.predicted;
  if (a.json) {
    nlohmann::json j;
    j["predicted_hz"] = {{"bpfo", p.bpfo_hz}, {"bpfi", p.bpfi_hz}, {"bsf", p.bsf_hz}, {"ftf", p.ftf_hz}};
    j["found_hz"] = {{"bpfo", opt(r.bpfo.harmonics[0].found_hz)},
                     {"bpfi", opt(r.bpfi.harmonics[0].found_hz)},
                     {"bsf", opt(r.found_bsf_hz)},
                     {"ftf", opt(r.ftf.harmonics[0].found_hz)}};
    j["verdict"] = r.verdict;
    j["reason"] = r.reason;
    j["shaft_hz"] = p.shaft_hz;
    j["bearing"] = std::string(geometry->name);
    j["band_hz"] = {r.band.low_hz, r.band.high_hz};
    j["band_kurtosis"] = r.band.kurtosis;
    j["discrete_removed"] = {{"enabled", a.remove_discrete},
                             {"bins", r.discrete.bins},
                             {"energy_fraction", r.discrete.energy_fraction}};
    nlohmann::json lines = nlohmann::json::array();
    for (const auto& l : r.strongest_lines) lines.push_back({{"hz", l.hz}, {"ratio", l.ratio}});
    j["strongest_lines"] = lines;
    j["ratio"] = {{"bpfo", r.bpfo.harmonics[0].ratio},
                  {"bpfi", r.bpfi.harmonics[0].ratio},
                  {"bsf", r.bsf.harmonics[0].ratio},
                  {"bsf2", r.bsf2.harmonics[0].ratio},
                  {"ftf", r.ftf.harmonics[0].ratio}};
    // score: -log10 of the corrected family p-value (significance; docs/bearing.md).
    j["score"] = {{"bpfo", r.bpfo.score}, {"bpfi", r.bpfi.score}, {"ball", r.bsf.score}, {"ftf", r.ftf.score}};
    j["detected"] = {{"bpfo", r.bpfo.evidence}, {"bpfi", r.bpfi.evidence}, {"ball", r.bsf.evidence},
                     {"ftf", r.ftf.evidence}};
    j["family_band_hz"] = {{"bpfo", {r.bpfo.band.low_hz, r.bpfo.band.high_hz}},
                           {"bpfi", {r.bpfi.band.low_hz, r.bpfi.band.high_hz}},
                           {"ball", {r.bsf.band.low_hz, r.bsf.band.high_hz}},
                           {"ftf", {r.ftf.band.low_hz, r.ftf.band.high_hz}}};
    j["fundamental_ratio"] = {{"bpfo", r.bpfo.strength}, {"bpfi", r.bpfi.strength}, {"ball", r.bsf.strength},
                              {"ftf", r.ftf.strength}};
    j["bands_tried"] = r.bands_tried;
    j["family_false_alarm"] = hb::BearingCheckOptions{}.family_false_alarm;
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("bearing %s at %.1f rpm (shaft %.3f Hz); resonance band %.0f-%.0f Hz (spectral kurtosis %.2f)\n",
              std::string(geometry->name).c_str(), a.rpm, p.shaft_hz, r.band.low_hz, r.band.high_hz,
              r.band.kurtosis);
  if (a.remove_discrete)
    std::printf("discrete components removed: %zu bins, %.1f %% of the energy (|X| > %.2f x local median)\n",
                r.discrete.bins, 100.0 * r.discrete.energy_fraction, r.discrete.threshold);
  std::printf("%-6s %12s %12s %10s %10s %s\n", "line", "predicted_Hz", "found_Hz", "ratio", "threshold", "harmonics");
  auto row = [](const char* name, const hb::FamilyResult& f, std::optional<double> found) {
    int n = 0;
    for (const auto& h : f.harmonics) n += h.stands_out() ? 1 : 0;
    const auto& l = f.harmonics[0];
    std::printf("%-6s %12.2f %12s %10.2f %10.2f %d/%zu\n", name, l.predicted_hz,
                found ? std::to_string(*found).substr(0, 8).c_str() : "-", l.ratio, l.threshold, n,
                f.harmonics.size());
  };
  row("bpfo", r.bpfo, r.bpfo.harmonics[0].found_hz);
  row("bpfi", r.bpfi, r.bpfi.harmonics[0].found_hz);
  row("bsf", r.bsf, r.bsf.harmonics[0].found_hz);
  row("2bsf", r.bsf2, r.bsf2.harmonics[0].found_hz);
  row("ftf", r.ftf, r.ftf.harmonics[0].found_hz);
  if (!r.strongest_lines.empty()) {
    std::printf("strongest envelope lines (Hz ratio x f_r x FTF):");
    for (const auto& l : r.strongest_lines)
      std::printf("%s %.2f %.1f %.3f %.3f", &l == &r.strongest_lines.front() ? "" : ";", l.hz, l.ratio,
                  l.hz / p.shaft_hz, l.hz / p.ftf_hz);
    std::printf("\n");
  }
  std::printf("families (-log10 p corrected for %zu bands x 4 families; detected if > 3):", r.bands_tried);
  for (const auto& [name, f] : {std::pair<const char*, const hb::FamilyResult*>{"bpfo", &r.bpfo}, {"bpfi", &r.bpfi},
                                {"ball", &r.bsf}, {"ftf", &r.ftf}})
    std::printf(" %s %.1f%s [%.0f-%.0f Hz]", name, f->score, f->evidence ? " detected" : "", f->band.low_hz,
                f->band.high_hz);
  std::printf("\n");
  std::printf("verdict: %s (%s)\n", r.verdict.c_str(), r.reason.c_str());
  return 0;
}

const amb::host::Registration reg{
    "bearing-check", "envelope analysis of a vibration record against a bearing's defect frequencies",
    [](CLI::App& sub, std::function<int()>& run_fn) {
      auto args = std::make_shared<Args>();
      namespace hc = amb::host::cli;
      hc::input_file(sub.add_option("--mat", args->mat_file, "MATLAB .mat file with the vibration record")->required(), "mat");
      sub.add_option("--var", args->var, "variable name of the record (e.g. DE_time)")->required();
      hc::real(sub.add_option("--fs", args->fs_hz, "sample rate, Hz")->required(), 100.0, 1e7, "Hz");
      hc::real(sub.add_option("--rpm", args->rpm, "nominal shaft speed, rpm")->required(), 1.0, 1e6, "rpm");
      sub.add_option("--bearing", args->bearing, "bearing name, one of: " + known_bearings())->required();
      sub.add_flag("--json", args->json, "print the figures as JSON");
      sub.add_flag("--remove-discrete", args->remove_discrete,
                   "edit discrete spectral lines (shaft harmonics, tones) out before band selection");
      run_fn = [args] { return run(*args); };
    }};

}  // namespace
