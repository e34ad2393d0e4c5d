// amb-firmware: the supervisor service. With `--backend sim` it runs against the simulated
// rig of its board file (software in the loop); the linux backend drives real I/O.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "boards/embedded_boards.hpp"
#include "firmware/board/board.hpp"
#include "firmware/common/cli_number.hpp"
#include "firmware/main/run_modes.hpp"

#ifndef AMB_VERSION
#error "AMB_VERSION is set from project(VERSION) in firmware/CMakeLists.txt"
#endif

namespace {

void usage() {
  std::printf(
      "usage: amb-firmware [--board NAME|PATH] [--backend sim|linux] [--duration-s S] [--paced]\n"
      "                    [--no-spin] [--no-analysis] [--sweep] [--list-boards] [--version]\n"
      "  --board       board file or embedded board name (default: %s)\n"
      "  --backend     override the board's backend\n"
      "  --duration-s  sim: seconds to hold at speed before landing, [0, 3600] (default 1.0);\n"
      "                linux: run time, [0, 3.15e7] s, 0 = until SIGTERM (default 0)\n"
      "  --paced       sim: pace the loop to wall time instead of as fast as possible\n"
      "  --no-spin     sim: levitate and land without spinning up\n"
      "  --no-analysis do not start the analysis thread (speed tracker, bearing task)\n"
      "  --sweep       sim: run the board's loop-sensitivity sweep ([sweep]) before landing and\n"
      "                store its event in memory (summary printed; amb-host sweep writes it)\n"
      "  --list-boards print the embedded board names\n"
      "  --version     print the version\n"
      "example:\n"
      "  amb-firmware --board bath-amb-rig --backend sim --duration-s 2\n"
      "exit status: 0 success, 1 bad input (the option or file is named), 2 the run failed\n",
      amb::boards::k_default_board);
}

}  // namespace

int main(int argc, char** argv) {
  amb::fwmain::RunOptions opt;
  opt.board = amb::boards::k_default_board;
  std::string backend;
  bool duration_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "amb-firmware: error: %s needs a value (see --help)\n", name);
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--board") opt.board = value("--board");
    else if (a == "--backend") backend = value("--backend");
    else if (a == "--duration-s") {
      const std::string why = amb::cli::check_number(value("--duration-s"), {0.0, 3.15e7, false, false, "s"}, &opt.duration_s);
      if (!why.empty()) {
        std::fprintf(stderr, "amb-firmware: error: --duration-s: %s\n", why.c_str());
        return 1;
      }
      duration_given = true;
    }
    else if (a == "--paced") opt.paced = true;
    else if (a == "--no-spin") opt.spin = false;
    else if (a == "--no-analysis") opt.analysis = false;
    else if (a == "--sweep") opt.sweep = true;
    else if (a == "--list-boards") {
      for (const auto& n : amb::board::embedded_board_names()) std::printf("%s\n", n.c_str());
      return 0;
    } else if (a == "--version") {
      std::printf("amb-firmware %s\n", AMB_VERSION);
      return 0;
    } else if (a == "--help" || a == "-h") {
      usage();
      return 0;
    } else {
      std::fprintf(stderr, "amb-firmware: error: unknown option '%s' (see --help)\n", a.c_str());
      return 1;
    }
  }
  amb::board::BoardConfig board;
  try {
    board = amb::board::load_board(opt.board);
  } catch (const amb::board::BoardError& e) {
    std::fprintf(stderr, "amb-firmware: error: --board: %s\n", e.what());
    return 1;
  }
  if (backend.empty()) backend = board.backend;
  // The sim backend runs the hold in simulated time as fast as it can: an hour is the most
  // that makes sense on a workstation.
  if (backend == "sim" && duration_given && opt.duration_s > 3600.0) {
    std::fprintf(stderr, "amb-firmware: error: --duration-s: '%g' is out of range for the sim backend; allowed [0, 3600] s\n",
                 opt.duration_s);
    return 1;
  }
  if (backend == "sim") return amb::fwmain::run_sim(board, opt);
  if (backend == "linux") return amb::fwmain::run_linux(board, opt);
  std::fprintf(stderr, "amb-firmware: error: --backend: '%s' is not available here (sim, linux)\n", backend.c_str());
  return 1;
}
