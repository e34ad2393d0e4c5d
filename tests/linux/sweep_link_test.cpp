// amb-host sweep --connect's path (issue 35) against the firmware over real libmodbus TCP on
// 127.0.0.1: the supervisor and loop of the slow target board on its simulated rig (loop and
// event writer in one thread, events in files as on a board), the register map behind a
// ModbusTcpServer; the host arms and starts the sweep with the board's key, polls its progress
// registers, finds the new sweep event in the list, downloads it (CRC-32C) and decodes it.
// A wrong key is refused before anything starts.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include "firmware/board/board.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/linux/file_storage.hpp"
#include "hal/linux/modbus_tcp_server.hpp"
#include "host-tools/core/sweep/sweep_acquire.hpp"
#include "tests/support/test_paths.hpp"

namespace {

namespace fs = std::filesystem;
constexpr uint32_t k_key = 0x5A17C0DE;

TEST(SweepLink, ArmStartPollAndDownloadOverModbus) {
  const fs::path dir = fs::temp_directory_path() / ("amb-sweep-link-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "events");
  const amb::board::BoardConfig b =
      amb::board::load_board(std::string(amb::test::source_dir()) + "/tests/target/arm-virt-tracker.toml");
  amb::sil::SilRig rig(b);
  amb::fw::FloatingCapture capture;
  amb::fw::configure_capture(capture, b);
  rig.set_sink(&capture);
  amb::hal::linux_hw::FileStorage events((dir / "events").string());
  amb::fw::WriterOptions wo;
  wo.run_diagnosis = false;
  amb::fw::EventWriter writer(capture, events, b, wo);
  writer.set_sweep_source(&rig.supervisor().sweep());
  // Levitate before the server starts (the loop thread below owns the rig from then on).
  rig.run_for(0.05);
  rig.supervisor().post(amb::fw::Command::levitate);
  ASSERT_TRUE(rig.run_until([](const amb::fw::Status& s) { return s.phase == amb::fw::Phase::levitated; }, 30.0));
  amb::fw::RegisterSources src;
  src.supervisor = &rig.supervisor();
  src.events = &events;
  src.sweep_store = [&] { return amb::fw::SweepStoreInfo{writer.sweeps_stored(), writer.last_sweep_number()}; };
  src.board_name = b.name;
  src.arm_key = k_key;
  src.rate_hz = b.rate_hz;
  amb::fw::RegisterMap map(src);
  amb::hal::linux_hw::ModbusTcpOptions mo;
  mo.bind_address = "127.0.0.1";
  mo.port = 0;
  amb::hal::linux_hw::ModbusTcpServer server(mo);
  std::string err;
  ASSERT_TRUE(server.start(map, err)) << err;
  std::atomic<bool> stop{false};
  std::thread loop([&] {
    // About 4x real time: 20 ms of loop, then 5 ms of sleep; the writer polled in between.
    while (!stop.load()) {
      rig.run_for(0.02);
      writer.poll();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  // Stop the loop (and the server) however the test leaves this scope.
  struct Joiner {
    std::atomic<bool>& stop;
    std::thread& t;
    amb::hal::linux_hw::ModbusTcpServer& s;
    ~Joiner() {
      stop.store(true);
      if (t.joinable()) t.join();
      s.stop();
    }
  } joiner{stop, loop, server};
  amb::host::link::LinkOptions lo;
  lo.port = server.bound_port();
  lo.retry_delay_s = 0.01;
  lo.response_timeout_s = 1.0;
  amb::host::sweep::AcquireOptions o;
  o.out_dir = (dir / "out").string();
  o.timeout_s = 60.0;
  o.poll_s = 0.05;
  int progress_lines = 0;
  o.progress = [&](const std::string&) { ++progress_lines; };
  // The wrong key: refused (arm exception 3), nothing starts.
  EXPECT_THROW(amb::host::sweep::acquire_sweep_modbus(lo, k_key + 1, o), amb::host::sweep::AcquireError);
  amb::host::sweep::AcquireResult r;
  ASSERT_NO_THROW(r = amb::host::sweep::acquire_sweep_modbus(lo, k_key, o));
  std::printf("[ RESULT ] sweep over Modbus: %s, %llu bytes, %zu axes, %zu lines, u/e recorded %zu samples; %d progress "
              "lines; refusals %u\n", r.event_name.c_str(), static_cast<unsigned long long>(r.event_bytes), r.record.axes.size(),
              r.record.plan.frequencies_hz.size(), r.record.axes.empty() ? 0 : r.record.axes[0].summing_point_a.size(),
              progress_lines, r.refusals);
  EXPECT_TRUE(fs::exists(r.event_path));
  EXPECT_EQ(fs::file_size(r.event_path), r.event_bytes);
  EXPECT_EQ(r.record.board_name, b.name);
  EXPECT_FALSE(r.record.aborted);
  ASSERT_EQ(r.record.axes.size(), 1u);
  EXPECT_EQ(r.record.axes[0].excitation_a.size(), static_cast<size_t>(b.sweep.recorded_periods) * b.sweep.samples_per_period);
  EXPECT_GT(progress_lines, 0);
  EXPECT_EQ(r.refusals, 0u);  // the wrong key failed at the arm, before the start
  fs::remove_all(dir);
}

}  // namespace
