// Event download throughput over the supervisory link: the board's register map served by the
// libmodbus TCP server on 127.0.0.1, downloaded by amb-host's link client (select + read in
// one function-23 transaction per 228-byte block, CRC-32C per block and end to end).
#if __has_include("host-tools/core/link/board_link.hpp") && defined(AMB_BENCH_HAVE_LINK)
#include <benchmark/benchmark.h>

#include <random>

#include "firmware/supervisory/register_map.hpp"
#include "hal/linux/modbus_tcp_server.hpp"
#include "hal/sim/sim_rig.hpp"
#include "host-tools/core/link/board_link.hpp"

namespace {

void BM_ModbusEventDownload(benchmark::State& state) {
  const size_t bytes = static_cast<size_t>(state.range(0));
  amb::hal::sim::MemoryStorage events(64u << 20);
  std::vector<uint8_t> blob(bytes);
  std::mt19937 rng(1);
  for (auto& b : blob) b = static_cast<uint8_t>(rng());
  std::string err;
  events.write_atomic("drop-bench.evt", blob, err);
  amb::fw::RegisterSources src;
  src.events = &events;
  src.board_name = "bench";
  amb::fw::RegisterMap map(src);
  amb::hal::linux_hw::ModbusTcpOptions o;
  o.bind_address = "127.0.0.1";
  o.port = 0;
  amb::hal::linux_hw::ModbusTcpServer server(o);
  if (!server.start(map, err)) {
    state.SkipWithError(err.c_str());
    return;
  }
  amb::host::link::LinkOptions lo;
  lo.port = server.bound_port();
  amb::host::link::ModbusLink link(lo);
  const auto list = amb::host::link::list_events(link);
  for (auto _ : state) {
    std::vector<uint8_t> got;
    amb::host::link::TransferStats s;
    amb::host::link::download(link, 0, list[0].crc32, list[0].size, got, s);
    benchmark::DoNotOptimize(got.data());
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(bytes));
  server.stop();
}
BENCHMARK(BM_ModbusEventDownload)->Arg(64 << 10)->Arg(1 << 20)->Unit(benchmark::kMillisecond);

}  // namespace
#endif
