// amb-host journal-sil: a steady record of the journal-bearing rig from software in the loop,
// with a wear put into the plant (the test data of `wear-id`). Logic:
// host-tools/core/wearid/journal_sil_record.hpp.
#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/wearid/journal_sil_record.hpp"

namespace {

struct Args {
  std::string out;
  std::string board = "unicamp-journal-rig";
  std::string wear = "none";
  double eccentricity = 0.1;
  double speed_hz = 34.0;
  double record_s = 2.0;
  unsigned long long seed = 1;
  double full_film_s = 0.0;
  double grid_tolerance = 2e-3;
  bool json = false;
};

// "none", "2p:D0_UM,GAMMA_DEG" or "3p:D0_UM,GAMMA_DEG,BETA_DEG".
bool parse_wear(const std::string& s, amb::model::journal::WearParams& w, std::string& why) {
  namespace mj = amb::model::journal;
  if (s == "none") {
    w = {};
    return true;
  }
  const auto colon = s.find(':');
  if (colon == std::string::npos) {
    why = "--wear must be none, 2p:D0_UM,GAMMA_DEG or 3p:D0_UM,GAMMA_DEG,BETA_DEG";
    return false;
  }
  const std::string kind = s.substr(0, colon);
  std::stringstream ss(s.substr(colon + 1));
  std::string item;
  double v[3] = {0, 0, 0};
  int n = 0;
  while (std::getline(ss, item, ',') && n < 3) {
    // Depth in um (0, 1000], position and span in degrees.
    const amb::cli::NumberRange r = n == 0 ? amb::cli::NumberRange{0.0, 1000.0, true, false, "um"}
                                           : amb::cli::NumberRange{-360.0, 360.0, false, false, "deg"};
    if (const std::string bad = amb::cli::check_number(item, r, &v[n]); !bad.empty()) {
      why = "--wear: " + bad;
      return false;
    }
    ++n;
  }
  if (kind == "2p" && n == 2) {
    w = {mj::WearModel::two_parameter, v[0] * 1e-6, v[1] * M_PI / 180.0, 0.0};
  } else if (kind == "3p" && n == 3) {
    w = {mj::WearModel::elliptical, v[0] * 1e-6, v[1] * M_PI / 180.0, v[2] * M_PI / 180.0};
  } else {
    why = "--wear must be none, 2p:D0_UM,GAMMA_DEG or 3p:D0_UM,GAMMA_DEG,BETA_DEG";
    return false;
  }
  return true;
}

int run(const Args& a) {
  amb::host::wearid::JournalSilOptions o;
  std::string why;
  if (!parse_wear(a.wear, o.wear, why)) {
    std::fprintf(stderr, "amb-host journal-sil: error: %s\n", why.c_str());
    return 1;
  }
  o.board = a.board;
  o.eccentricity = a.eccentricity;
  o.speed_hz = a.speed_hz;
  o.record_s = a.record_s;
  o.noise_seed = a.seed;
  o.full_film_s = a.full_film_s;
  o.grid_tolerance = a.grid_tolerance;
  amb::host::wearid::JournalSilSummary s;
  try {
    s = amb::host::wearid::record_journal_sil(o, a.out);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "amb-host journal-sil: error: %s\n", e.what());
    return 1;
  } catch (const amb::board::BoardError& e) {
    std::fprintf(stderr, "amb-host journal-sil: error: --board: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "amb-host journal-sil: error: %s\n", e.what());
    return 2;
  }
  if (!s.ok) {
    std::fprintf(stderr, "amb-host journal-sil: error: %s\n", s.message.c_str());
    return 2;
  }
  std::fprintf(stderr, "journal-sil: wrote %s.csv / %s.json\n", a.out.c_str(), a.out.c_str());
  if (std::isfinite(s.grid_error_estimate))
    std::fprintf(stderr, "journal-sil: film grid %d x %d, estimated K/C error %.3f %% (tolerance %.3f %%%s)\n", s.grid_theta,
                 s.grid_axial, 100.0 * s.grid_error_estimate, 100.0 * a.grid_tolerance,
                 s.grid_converged ? "" : ", NOT reached within the grid limits");
  else
    std::fprintf(stderr, "journal-sil: film grid %d x %d (the board's; --grid-tolerance 0: error not estimated)\n",
                 s.grid_theta, s.grid_axial);
  if (a.json) {
    nlohmann::json j = {{"speed_hz", s.speed_hz},
                              {"static_eccentricity", s.static_eccentricity},
                              {"journal_orbit_peak_um", s.orbit_peak_m * 1e6},
                              {"simulated_s", s.sim_s},
                              {"film_grid",
                               {{"cells_theta", s.grid_theta},
                                {"cells_axial", s.grid_axial},
                                {"tolerance", a.grid_tolerance},
                                {"error_estimate", s.grid_error_estimate},
                                {"converged", s.grid_converged}}}};
    if (!std::isfinite(s.grid_error_estimate)) j["film_grid"]["error_estimate"] = nullptr;
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("speed %.3f Hz, journal static eccentricity %.3f, orbit peak %.2f um (clearance %.0f um)\n", s.speed_hz,
                s.static_eccentricity, s.orbit_peak_m * 1e6, s.journal_clearance_m * 1e6);
  }
  return 0;
}

void declare(CLI::App& sub, Args& args) {
  namespace hc = amb::host::cli;
  hc::output_file(sub.add_option("--out", args.out, "output stem (writes STEM.csv and STEM.json)")->required());
  hc::input_file(sub.add_option("--board", args.board, "board with a [journal_bearing]"), "board");
  sub.add_option("--wear", args.wear, "none | 2p:D0_UM,GAMMA_DEG | 3p:D0_UM,GAMMA_DEG,BETA_DEG");
  hc::real(sub.add_option("--eccentricity", args.eccentricity, "static eccentricity ratio the AMBs hold"), 0.0, 0.9);
  hc::number(sub.add_option("--speed", args.speed_hz, "steady speed, Hz"), {1.0, 500.0, true, false, "Hz"});
  hc::number(sub.add_option("--record", args.record_s, "recorded time, s"), {0.2, 600.0, true, false, "s"});
  hc::whole(sub.add_option("--seed", args.seed, "sensor-noise seed"), 0, 9.0e15);
  hc::real(sub.add_option("--full-film", args.full_film_s,
                          "full (nonlinear) Reynolds film in the plant from this long before the end of the settle, s "
                          "(0: linear film element only)"),
           0.0, 600.0, "s");
  hc::real(sub.add_option("--grid-tolerance", args.grid_tolerance,
                          "film grid refined at the static journal position until the estimated K/C error is below "
                          "this (relative; 0: the board's grid)"),
           0.0, 0.49);
  sub.add_flag("--json", args.json, "print the figures as JSON");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "journal-sil", "steady SIL record of the journal-bearing rig with a given wear (test data for wear-id)", declare, run);

}  // namespace
