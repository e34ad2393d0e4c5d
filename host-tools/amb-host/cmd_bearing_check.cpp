// amb-host bearing-check: rolling-bearing diagnosis of a measured record (pre-whitening, SK band
// selection, envelope spectrum, family scores against a surrogate null). Logic:
// host-tools/core/bearing/bearing_check.hpp.
#include <algorithm>
#include <cmath>
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
#include "host-tools/core/io/number_text.hpp"
#include "host-tools/core/report/bearing_page.hpp"
#include "host-tools/core/report/page_file.hpp"
#include "model/bearing/catalogue.hpp"
#include "model/bearing/geometry.hpp"

namespace {

using amb::host::io::printf_text;

namespace mb = amb::model::bearing;
namespace hb = amb::host::bearing;

struct Args {
  std::string mat_file;
  std::string var;
  std::string end;  // "drive" / "fan" (CWRU channel and bearing defaults)
  std::optional<double> fs_hz;
  std::optional<double> rpm;
  std::string bearing;
  bool raw_cage_scan = false;
  std::string plot;  // HTML page with the envelope spectra ("": none)
  bool json = false;
};

// Plausible ranges: a vibration record sampled below 1 kHz cannot carry bearing resonances;
// above 10 MHz is no accelerometer DAQ. Speeds from 1 rpm to 1e6 rpm.
constexpr double k_fs_min_hz = 1000.0, k_fs_max_hz = 1e7;
constexpr double k_rpm_min = 1.0, k_rpm_max = 1e6;

nlohmann::json opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

std::string known_bearings() {
  std::string known;
  for (const auto& g : amb::model::bearing::bearing_catalogue()) known += (known.empty() ? "" : ", ") + std::string(g.name);
  return known;
}

int bad_input(const std::string& what) {
  std::fprintf(stderr, "amb-host bearing-check: error: %s\n", what.c_str());
  return 1;
}
void warn(const std::string& what) { std::fprintf(stderr, "amb-host bearing-check: warning: %s\n", what.c_str()); }

// A scalar of the file, if it has one that is a finite number.
std::optional<double> file_scalar(const std::string& file, const std::string& name) {
  try {
    for (const auto& v : amb::host::list_mat_variables(file))
      if (v == name) {
        const double x = amb::host::read_mat_scalar(file, name);
        if (std::isfinite(x)) return x;
      }
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

// Command line vs file: the file's value is the record's own; the command line's is used only
// when the file has none. Disagreement (> 0.1 %) is warned about.
std::optional<double> resolve(const char* option, const std::optional<double>& cli, const std::optional<double>& file,
                              const char* file_var) {
  if (file && cli && std::abs(*cli - *file) > 1e-3 * std::abs(*file))
    warn(std::string(option) + " " + printf_text("%.6g", *cli) + " disagrees with the file's " + file_var + " = " + printf_text("%.6g", *file) +
         "; using the file's value");
  return file ? file : cli;
}

void json_line(nlohmann::json& arr, const hb::LineScore& l) {
  arr.push_back({{"label", l.label}, {"hz", l.hz}, {"ratio", l.ratio}, {"p_value", l.p_value}});
}

int run(Args a) {
  if (!std::filesystem::exists(a.mat_file)) return bad_input("--mat file '" + a.mat_file + "' does not exist");
  // Non-finite or absurd values are refused before anything else is read.
  if (a.fs_hz && !(std::isfinite(*a.fs_hz) && *a.fs_hz >= k_fs_min_hz && *a.fs_hz <= k_fs_max_hz))
    return bad_input("--fs " + printf_text("%.6g", *a.fs_hz) + " is not a sample rate in [" + printf_text("%.6g", k_fs_min_hz) + ", " + printf_text("%.6g", k_fs_max_hz) +
                     "] Hz");
  if (a.rpm && !(std::isfinite(*a.rpm) && *a.rpm >= k_rpm_min && *a.rpm <= k_rpm_max))
    return bad_input("--rpm " + printf_text("%.6g", *a.rpm) + " is not a shaft speed in [" + printf_text("%.6g", k_rpm_min) + ", " + printf_text("%.6g", k_rpm_max) +
                     "] rpm");
  if (!a.end.empty() && a.end != "drive" && a.end != "fan")
    return bad_input("--end '" + a.end + "' must be 'drive' or 'fan'");
  // CWRU convention: the drive end's accelerometer DE_time sits on the 6205, the fan end's
  // FE_time on the 6203.
  const bool fan = a.end == "fan" || (a.end.empty() && a.var == "FE_time");
  if (a.var.empty()) a.var = fan ? "FE_time" : "DE_time";
  if (a.bearing.empty()) a.bearing = fan ? "6203" : "6205";
  const auto geometry = mb::find_bearing(a.bearing);
  if (!geometry) return bad_input("--bearing: unknown bearing '" + a.bearing + "' (known: " + known_bearings() + ")");
  // The record first: a file that cannot be read is named before anything is taken from it.
  std::vector<double> x;
  try {
    x = amb::host::read_mat_vector(a.mat_file, a.var);
  } catch (const std::exception& e) {
    return bad_input("--mat '" + a.mat_file + "' --var '" + a.var + "': " + e.what());
  }
  const auto fs = resolve("--fs", a.fs_hz, file_scalar(a.mat_file, "fs"), "fs");
  const auto rpm = resolve("--rpm", a.rpm, file_scalar(a.mat_file, "RPM"), "RPM");
  if (!fs) return bad_input("--fs is needed: the file has no scalar 'fs'");
  if (!rpm) return bad_input("--rpm is needed: the file has no scalar 'RPM'");
  if (!(*fs >= k_fs_min_hz && *fs <= k_fs_max_hz))
    return bad_input("the file's fs " + printf_text("%.6g", *fs) + " is not a sample rate in [" + printf_text("%.6g", k_fs_min_hz) + ", " +
                     printf_text("%.6g", k_fs_max_hz) + "] Hz");
  if (!(*rpm >= k_rpm_min && *rpm <= k_rpm_max))
    return bad_input("the file's RPM " + printf_text("%.6g", *rpm) + " is not a shaft speed in [" + printf_text("%.6g", k_rpm_min) + ", " +
                     printf_text("%.6g", k_rpm_max) + "] rpm");
  // Where the record cannot hold the defect lines, say so instead of giving a verdict: every
  // line examined must lie below the Nyquist frequency, and the record must span enough
  // revolutions of the cage (the slowest line) to resolve it.
  const int harmonics = hb::BearingCheckOptions{}.harmonics;
  const mb::DefectFrequencies defect = mb::defect_frequencies(*geometry, *rpm / 60.0);
  const double highest_hz = harmonics * defect.bpfi_hz + 3.0 * defect.shaft_hz;
  if (highest_hz >= 0.5 * *fs)
    return bad_input("--rpm " + printf_text("%.6g", *rpm) + " with --fs " + printf_text("%.6g", *fs) + ": the defect lines examined reach " +
                     printf_text("%.6g", highest_hz) + " Hz (" + std::to_string(harmonics) +
                     " x BPFI + 3 x shaft), above the Nyquist frequency " + printf_text("%.6g", 0.5 * *fs) +
                     " Hz; nothing can be analysed (check --rpm and --fs)");
  const double duration_s = static_cast<double>(x.size()) / *fs;
  if (duration_s * defect.ftf_hz < 10.0)
    return bad_input("--rpm " + printf_text("%.6g", *rpm) + " with --fs " + printf_text("%.6g", *fs) + ": the record (" +
                     std::to_string(x.size()) + " samples, " + printf_text("%.6g", duration_s) + " s) spans " +
                     printf_text("%.6g", duration_s * defect.ftf_hz) + " cage revolutions; at least 10 are needed to resolve the lines "
                     "(check --rpm and --fs)");
  hb::BearingCheckResult r;
  try {
    hb::BearingCheckOptions o;
    o.raw_cage_scan = a.raw_cage_scan;
    o.keep_spectra = !a.plot.empty();
    r = hb::check_bearing(x, *fs, *rpm / 60.0, *geometry, o);
  } catch (const std::invalid_argument& e) {
    return bad_input(std::string(e.what()) + " (--fs " + printf_text("%.6g", *fs) + ", --rpm " + printf_text("%.6g", *rpm) + ")");
  }
  if (!a.plot.empty()) {
    amb::host::report::BearingPageInfo info{std::filesystem::path(a.mat_file).filename().string(), a.var,
                                            std::string(geometry->name), *fs, *rpm};
    try {
      const std::string written =
          amb::host::report::write_page_file(amb::host::report::render_bearing_page(r, info), a.plot, "bearing page");
      std::fprintf(stderr, "bearing page: %s\n", written.c_str());
    } catch (const std::exception& e) {
      return bad_input(std::string("--plot: ") + e.what());
    }
  }
  const auto& p = r.predicted;
  const auto& q = r.refined;
  auto fam = [&](const char* n) -> const hb::FamilyResult& { return r.family(n); };
  if (a.json) {
    nlohmann::json j;
    j["predicted_hz"] = {{"bpfo", p.bpfo_hz}, {"bpfi", p.bpfi_hz}, {"bsf", p.bsf_hz}, {"ftf", p.ftf_hz}};
    j["refined_hz"] = {{"shaft", q.shaft_hz}, {"bpfo", q.bpfo_hz}, {"bpfi", q.bpfi_hz}, {"bsf", q.bsf_hz}, {"ftf", q.ftf_hz}};
    j["found_hz"] = {{"bpfo", opt(fam("bpfo").found_hz)},
                     {"bpfi", opt(fam("bpfi").found_hz)},
                     {"bsf", opt(fam("ball").found_hz)},
                     {"ftf", opt(fam("ftf").found_hz)}};
    j["verdict"] = r.verdict;
    j["reason"] = r.reason;
    j["bearing"] = std::string(geometry->name);
    j["variable"] = a.var;
    j["fs_hz"] = *fs;
    j["rpm"] = *rpm;
    j["shaft_hz"] = p.shaft_hz;
    j["speed"] = {{"nominal_hz", r.speed.nominal_hz},
                  {"refined_hz", r.speed.speed_hz},
                  {"refined", r.speed.refined},
                  {"source", r.speed_source},
                  {"log10_p", r.speed.log10_p},
                  {"harmonics_present", r.speed.harmonics_present}};
    j["whitening"] = r.whitening;
    nlohmann::json bands = nlohmann::json::array();
    for (const auto& b : r.bands) {
      nlohmann::json jb = {{"name", b.name}, {"low_hz", b.band.low_hz}, {"high_hz", b.band.high_hz}};
      // The EES combines sub-bands and has no spectral kurtosis of its own.
      if (b.sub_bands > 0)
        jb["sub_bands"] = b.sub_bands;
      else
        jb["spectral_kurtosis"] = b.band.kurtosis;
      bands.push_back(jb);
    }
    j["bands"] = bands;
    j["threshold_log10_p"] = r.threshold_log10_p;
    j["record_false_alarm"] = hb::BearingCheckOptions{}.record_false_alarm;
    nlohmann::json fams = nlohmann::json::object();
    for (const auto& f : r.families) {
      nlohmann::json lines = nlohmann::json::array();
      for (const auto& l : f.lines.lines) json_line(lines, l);
      fams[f.name] = {{"predicted_hz", f.predicted_hz},
                      {"found_hz", opt(f.found_hz)},
                      {"score", f.score},
                      {"log10_p", f.log10_p},
                      {"log10_p_per_band", f.log10_p_per_band},
                      {"threshold_score", f.threshold_score},
                      {"band", r.bands[f.band_index].name},
                      {"slip", f.lines.delta},
                      {"fundamental_present", f.lines.fundamental_present},
                      {"detected", f.detected},
                      {"unique_score", f.unique_score},
                      {"reason", f.reason},
                      {"lines", lines}};
    }
    j["families"] = fams;
    const auto& rc = r.raw_cage;
    if (rc.run) {
      nlohmann::json lines = nlohmann::json::array();
      for (const auto& l : rc.lines.lines) json_line(lines, l);
      j["raw_cage_scan"] = {{"bands", rc.bands},
                            {"low_hz", rc.band.low_hz},
                            {"high_hz", rc.band.high_hz},
                            {"score", rc.score},
                            {"log10_p", rc.log10_p},
                            {"threshold_log10_p", rc.threshold_log10_p},
                            {"threshold_score", rc.threshold_score},
                            {"detected", rc.detected},
                            {"null", {{"surrogates", rc.null.samples}, {"median", rc.null.median}, {"q99", rc.null.q99}, {"scale", rc.null.scale}}},
                            {"lines", lines}};
    } else {
      j["raw_cage_scan"] = nullptr;
    }
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("bearing %s on %s, fs %.0f Hz, %.1f rpm nominal (shaft %.3f Hz)\n", std::string(geometry->name).c_str(),
              a.var.c_str(), *fs, *rpm, p.shaft_hz);
  std::printf("1 pre-whitening: %s\n", r.whitening.c_str());
  std::printf("2 bands:");
  for (const auto& b : r.bands) {
    if (b.sub_bands > 0)
      std::printf(" %s %.0f-%.0f Hz (%zu bands of %.0f Hz);", b.name.c_str(), b.band.low_hz, b.band.high_hz, b.sub_bands,
                  (b.band.high_hz - b.band.low_hz) / static_cast<double>(b.sub_bands));
    else
      std::printf(" %s %.0f-%.0f Hz (SK %.2f);", b.name.c_str(), b.band.low_hz, b.band.high_hz, b.band.kurtosis);
  }
  const bool ees = std::any_of(r.bands.begin(), r.bands.end(), [](const hb::AnalysisBand& b) { return b.sub_bands > 0; });
  std::printf("\n3 envelope spectrum of each band%s\n",
              ees ? " (whitened_ees: the bands' envelope spectra over their floors, combined)" : "");
  std::printf("5 speed: %s %.4f Hz (from the %s; comb log10 p %.1f, %d harmonics present)\n",
              r.speed.refined ? "refined to" : "not refined, nominal", r.speed.speed_hz, r.speed_source.c_str(),
              r.speed.log10_p, r.speed.harmonics_present);
  std::printf("4/6 families (detected if log10 P_null < %.2f and the fundamental is present):\n", r.threshold_log10_p);
  std::printf("  %-5s %10s %10s %8s %10s %-13s %s\n", "family", "pred_Hz", "found_Hz", "score", "log10P", "band",
              "decision");
  for (const auto& f : r.families)
    std::printf("  %-5s %10.2f %10s %8.1f %10.1f %-13s %s\n", f.name.c_str(), f.predicted_hz,
                f.found_hz ? printf_text("%.6g", std::round(*f.found_hz * 100) / 100).c_str() : "-", f.score, f.log10_p,
                r.bands[f.band_index].name.c_str(), f.reason.c_str());
  const auto& rc = r.raw_cage;
  if (rc.run)
    std::printf("6 raw cage scan (nothing detected in the whitened bands): %zu raw bands, best %.0f-%.0f Hz score %.1f, "
                "threshold %.1f (log10 P %.1f vs %.1f; null: the record's own %d surrogates, median %.2f, q99 %.2f): %s\n",
                rc.bands, rc.band.low_hz, rc.band.high_hz, rc.score, rc.threshold_score, rc.log10_p, rc.threshold_log10_p,
                rc.null.samples, rc.null.median, rc.null.q99, rc.detected ? "detected" : "not detected");
  std::printf("verdict: %s (%s)\n", r.verdict.c_str(), r.reason.c_str());
  return 0;
}

std::string catalogue_text() {
  std::string s = "Bearing catalogue (--bearing; orders per shaft Hz):\n";
  char b[512];
  for (const auto& g : mb::bearing_catalogue()) {
    const auto o = mb::defect_orders(g);
    std::snprintf(b, sizeof b, "  %-9s Z %d, ball %.3f mm, pitch %.2f mm: BPFO %.4f BPFI %.4f BSF %.4f FTF %.4f  [%s]\n",
                  std::string(g.name).c_str(), g.ball_count, g.ball_diameter_m * 1e3, g.pitch_diameter_m * 1e3, o.bpfo,
                  o.bpfi, o.bsf, o.ftf, std::string(g.source).c_str());
    s += b;
  }
  s += "CWRU records: drive end DE_time on the SKF 6205 (default), fan end FE_time on the SKF 6203 (--end fan).\n";
  return s;
}

void declare(CLI::App& sub, Args& args) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("--mat", args.mat_file, "MATLAB .mat file with the vibration record")->required(), "mat");
  sub.add_option("--var", args.var, "variable of the record (default DE_time; FE_time with --end fan)");
  sub.add_option("--end", args.end, "CWRU end: drive (DE_time, SKF 6205) or fan (FE_time, SKF 6203)");
  hc::real(sub.add_option("--fs", args.fs_hz, "sample rate, Hz (default: the file's 'fs'; the file's value wins)"),
           k_fs_min_hz, k_fs_max_hz, "Hz");
  hc::real(sub.add_option("--rpm", args.rpm, "nominal shaft speed, rpm (default: the file's 'RPM'; the file's value wins)"),
           k_rpm_min, k_rpm_max, "rpm");
  sub.add_option("--bearing", args.bearing, "bearing name from the catalogue below, e.g. 'SKF 6205' or 6205");
  sub.add_flag("--raw-cage-scan", args.raw_cage_scan,
               "when nothing is detected, also scan the raw envelope for cage-rate modulation and read it as a ball "
               "fault (off: it names 6.8 % of healthy model bearings with ordinary ball-size variation 'ball'; "
               "docs/bearing.md)");
  hc::output_file(sub.add_option("--plot", args.plot,
                                 "write an HTML page with every band's envelope spectrum and the families' lines to this file"));
  sub.add_flag("--json", args.json, "print the figures as JSON");
  sub.footer(catalogue_text());
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "bearing-check", "rolling-bearing diagnosis of a vibration record (pre-whitening, SK band, envelope, family scores)", declare, run);

}  // namespace
