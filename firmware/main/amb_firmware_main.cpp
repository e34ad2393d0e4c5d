// amb-firmware: the supervisor service. With `--backend sim` it runs against the simulated
// rig of its board file (software in the loop); the linux backend drives real I/O.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "boards/embedded_boards.hpp"
#include "firmware/board/board.hpp"
#include "firmware/main/run_modes.hpp"

namespace {

void usage() {
  std::printf(
      "usage: amb-firmware [--board NAME|PATH] [--backend sim|linux] [--duration-s S] [--paced]\n"
      "                    [--no-spin] [--no-analysis] [--list-boards]\n"
      "  --board       board file or embedded board name (default: %s)\n"
      "  --backend     override the board's backend\n"
      "  --duration-s  sim: seconds to hold at speed before landing (default 1.0);\n"
      "                linux: run time, 0 = until SIGTERM (default 0)\n"
      "  --paced       sim: pace the loop to wall time instead of as fast as possible\n"
      "  --no-spin     sim: levitate and land without spinning up\n"
      "  --no-analysis do not start the analysis thread (speed tracker, bearing task)\n",
      amb::boards::k_default_board);
}

}  // namespace

int main(int argc, char** argv) {
  amb::fwmain::RunOptions opt;
  opt.board = amb::boards::k_default_board;
  std::string backend;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "amb-firmware: %s needs a value\n", name);
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--board") opt.board = value("--board");
    else if (a == "--backend") backend = value("--backend");
    else if (a == "--duration-s") opt.duration_s = std::atof(value("--duration-s").c_str());
    else if (a == "--paced") opt.paced = true;
    else if (a == "--no-spin") opt.spin = false;
    else if (a == "--no-analysis") opt.analysis = false;
    else if (a == "--list-boards") {
      for (const auto& n : amb::board::embedded_board_names()) std::printf("%s\n", n.c_str());
      return 0;
    } else if (a == "--help" || a == "-h") {
      usage();
      return 0;
    } else {
      std::fprintf(stderr, "amb-firmware: unknown option '%s' (see --help)\n", a.c_str());
      return 1;
    }
  }
  amb::board::BoardConfig board;
  try {
    board = amb::board::load_board(opt.board);
  } catch (const amb::board::BoardError& e) {
    std::fprintf(stderr, "amb-firmware: %s\n", e.what());
    return 1;
  }
  if (backend.empty()) backend = board.backend;
  if (backend == "sim") return amb::fwmain::run_sim(board, opt);
  if (backend == "linux") return amb::fwmain::run_linux(board, opt);
  std::fprintf(stderr, "amb-firmware: backend '%s' is not available here (sim, linux)\n", backend.c_str());
  return 1;
}
