// amb-plant: the HIL bench plant emulator. Pretends to be the rig's sensor and amplifier nodes
// on the CAN field bus (SocketCAN), around the same plant model the sim backend uses
// (amb::sil::make_board_plant). Runs until SIGTERM/SIGINT or --duration-s.
#include <poll.h>
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "firmware/board/board.hpp"
#include "firmware/common/cli_number.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "hal/linux/linux_clock.hpp"
#include "hal/linux/socketcan_bus.hpp"
#include "host-tools/amb-plant/bench_nodes.hpp"

namespace {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_report{false};
void on_signal(int) { g_stop.store(true); }
void on_report(int) { g_report.store(true); }

void usage() {
  std::printf(
      "usage: amb-plant --board NAME|PATH [--can IFACE] [--seed N] [--levitated] [--duration-s S] [--version]\n"
      "  HIL plant emulator: the board's sensor and amplifier nodes on the CAN field bus.\n"
      "  --can IFACE     SocketCAN interface (default: the board file's comms.can.interface)\n"
      "  --seed N        sensor-noise seed, whole number in [0, 9.0e15] (default 1)\n"
      "  --levitated     start with the rotor centred instead of on the touchdown bearings\n"
      "  --duration-s S  stop after S seconds, (0, 3.15e7] (default: until SIGTERM)\n"
      "  --version       print the version\n"
      "  SIGUSR1 prints the plant's true rotor speed and its time (the HIL reference for the\n"
      "  board's tracked speed).\n"
      "example:\n"
      "  amb-plant --board arm-virt-hil --can vcan0 --duration-s 60\n"
      "exit status: 0 success, 1 bad input (the option or file is named), 2 the run failed\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string board_name, iface;
  uint64_t seed = 1;
  bool levitated = false;
  double duration_s = -1.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "amb-plant: error: %s needs a value (see --help)\n", a.c_str());
        std::exit(1);
      }
      return argv[++i];
    };
    if (a == "--board") board_name = value();
    else if (a == "--can") iface = value();
    else if (a == "--seed" || a == "--duration-s") {
      // One rule for every number (firmware/common/cli_number.hpp): finite, in range, the
      // option named in the error.
      const bool is_seed = a == "--seed";
      const amb::cli::NumberRange r = is_seed ? amb::cli::NumberRange{0.0, 9.0e15, false, true, ""}
                                              : amb::cli::NumberRange{0.0, 3.15e7, true, false, "s"};
      double v = 0.0;
      const std::string why = amb::cli::check_number(value(), r, &v);
      if (!why.empty()) {
        std::fprintf(stderr, "amb-plant: error: %s: %s\n", a.c_str(), why.c_str());
        return 1;
      }
      if (is_seed) seed = static_cast<uint64_t>(v);
      else duration_s = v;
    }
    else if (a == "--levitated") levitated = true;
    else if (a == "--version") {
      std::printf("amb-plant %s\n", AMB_VERSION);
      return 0;
    } else if (a == "--help" || a == "-h") {
      usage();
      return 0;
    } else {
      std::fprintf(stderr, "amb-plant: error: unknown option '%s' (see --help)\n", a.c_str());
      return 1;
    }
  }
  if (board_name.empty()) {
    usage();
    std::fprintf(stderr, "amb-plant: error: --board is required\n");
    return 1;
  }
  amb::board::BoardConfig board;
  try {
    board = amb::board::load_board(board_name);
  } catch (const amb::board::BoardError& e) {
    std::fprintf(stderr, "amb-plant: error: --board: %s\n", e.what());
    return 1;
  }
  if (iface.empty()) iface = board.comms.can.interface;
  auto plant = amb::sil::make_board_plant(board, seed);
  plant->reset(levitated, 0.0);

  namespace fb = amb::fieldbus;
  const auto& c = board.comms.can;
  amb::hal::linux_hw::SocketCanBus bus;
  amb::hal::linux_hw::SocketCanOptions o;
  o.interface = iface;
  o.fd = c.fd;
  for (uint32_t fn : {fb::k_demand, fb::k_drive, fb::k_demand_fd}) o.filters.push_back({fn + c.amplifier_node_id, 0x7FF, false});
  o.filters.push_back({static_cast<uint32_t>(fb::k_heartbeat + c.board_node_id), 0x7FF, false});
  std::string err;
  if (!bus.open(o, err)) {
    std::fprintf(stderr, "amb-plant: error: --can %s: %s\n", iface.c_str(), err.c_str());
    return 2;
  }
  amb::plant::BenchNodes nodes(*plant, board, bus);
  struct sigaction sa{};
  sa.sa_handler = on_signal;
  ::sigaction(SIGTERM, &sa, nullptr);
  ::sigaction(SIGINT, &sa, nullptr);
  struct sigaction su{};
  su.sa_handler = on_report;
  ::sigaction(SIGUSR1, &su, nullptr);
  std::printf("amb-plant: ready: board %s, CAN %s%s, nodes sensor %u amplifier %u, %.0f Hz period lock, "
              "loop delay %.2f periods\n",
              board.name.c_str(), iface.c_str(), c.fd ? " (FD)" : "", c.sensor_node_id, c.amplifier_node_id,
              board.rate_hz, board.loop_delay_periods);
  std::fflush(stdout);
  const int64_t t0 = amb::hal::linux_hw::monotonic_ns();
  while (!g_stop.load()) {
    pollfd p{bus.fd(), POLLIN, 0};
    ::poll(&p, 1, 10);
    const int64_t now = amb::hal::linux_hw::monotonic_ns();
    amb::hal::CanFrame f;
    // Bounded: a plant slower than the board (e.g. under emulation) must still see SIGTERM.
    for (int k = 0; k < 64 && !g_stop.load() && bus.receive(f); ++k) nodes.on_frame(f, now);
    nodes.tick(now);
    if (g_report.exchange(false)) {
      std::printf("amb-plant: true speed %.4f Hz at plant time %.3f s (%llu periods stepped)\n",
                  plant->outputs().spin_speed_hz, static_cast<double>(nodes.counters().demands) / board.rate_hz,
                  static_cast<unsigned long long>(nodes.counters().demands));
      std::fflush(stdout);
    }
    if (duration_s > 0 && now - t0 > static_cast<int64_t>(duration_s * 1e9)) break;
  }
  const auto& n = nodes.counters();
  const auto s = bus.stats();
  std::printf("amb-plant: stopped: %llu periods stepped, %llu drive, %llu board heartbeats, %llu malformed, "
              "%llu board timeouts; CAN tx %llu rx %llu tx_dropped %llu rx_dropped %llu\n",
              static_cast<unsigned long long>(n.demands), static_cast<unsigned long long>(n.drives),
              static_cast<unsigned long long>(n.board_heartbeats), static_cast<unsigned long long>(n.malformed),
              static_cast<unsigned long long>(n.board_timeouts), static_cast<unsigned long long>(s.tx_frames),
              static_cast<unsigned long long>(s.rx_frames), static_cast<unsigned long long>(s.tx_dropped),
              static_cast<unsigned long long>(s.rx_dropped));
  std::printf("amb-plant: board round trip (sample frame sent -> demand frame received, wall time): %llu periods, "
              "p50 %.0f us, p99 %.0f us, p99.9 %.0f us, max %.0f us\n",
              static_cast<unsigned long long>(n.round_trips), static_cast<double>(n.round_trip_quantile_ns(0.5)) * 1e-3,
              static_cast<double>(n.round_trip_quantile_ns(0.99)) * 1e-3,
              static_cast<double>(n.round_trip_quantile_ns(0.999)) * 1e-3, static_cast<double>(n.max_round_trip_ns) * 1e-3);
  return 0;
}
