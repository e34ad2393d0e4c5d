// amb-host's side of the supervisory link against the board's register map, both over real
// libmodbus TCP on 127.0.0.1: event download (end-to-end CRC, resume after dropped
// connections and from a partial file), wear-record write-back (validated, persisted on a
// file storage, still there after a "restart"), and download throughput.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "firmware/board/board.hpp"
#include "firmware/persistence/crc32c.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/linux/file_storage.hpp"
#include "hal/linux/modbus_tcp_server.hpp"
#include "host-tools/core/link/board_link.hpp"
#include "tests/linux/flaky_proxy.hpp"

namespace {

namespace lk = amb::host::link;
using amb::hal::linux_hw::FileStorage;

constexpr uint32_t k_arm_key = 0x5EC0DE42;  // the test board's [comms.modbus] arm_key

struct Board {
  std::string dir;
  amb::board::BoardConfig board = amb::board::load_board("bath-amb-rig");
  amb::fw::Supervisor sup;
  std::unique_ptr<FileStorage> events, wear_fs;
  std::unique_ptr<amb::fw::WearStore> wear;
  std::unique_ptr<amb::fw::RegisterMap> map;
  std::unique_ptr<amb::hal::linux_hw::ModbusTcpServer> server;

  explicit Board(const std::string& d) : dir(d) {
    sup.configure(board);
    std::filesystem::create_directories(dir);
    events = std::make_unique<FileStorage>(dir + "/events");
    wear_fs = std::make_unique<FileStorage>(dir + "/wear");
    wear = std::make_unique<amb::fw::WearStore>(*wear_fs, board.name);
    const auto rep = wear->open();
    amb::fw::RegisterSources src;
    src.supervisor = &sup;
    src.events = events.get();
    src.wear = wear.get();
    src.wear_corrupt_at_start = rep.corrupt_slots;
    src.board_name = board.name;
    src.arm_key = k_arm_key;
    map = std::make_unique<amb::fw::RegisterMap>(src);
    amb::hal::linux_hw::ModbusTcpOptions o;
    o.bind_address = "127.0.0.1";
    o.port = 0;
    server = std::make_unique<amb::hal::linux_hw::ModbusTcpServer>(o);
    std::string err;
    if (!server->start(*map, err)) throw std::runtime_error(err);
  }
  lk::LinkOptions link(uint16_t port = 0) const {
    lk::LinkOptions o;
    o.port = port ? port : server->bound_port();
    o.retry_delay_s = 0.01;
    o.response_timeout_s = 1.0;
    return o;
  }
};

std::string temp_dir(const std::string& tag) {
  auto p = std::filesystem::temp_directory_path() / ("amb-link-test-" + tag + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  return p.string();
}

std::vector<uint8_t> blob(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> v(n);
  for (auto& b : v) b = static_cast<uint8_t>(rng());
  return v;
}

amb::fw::WearRecord record(uint32_t seq) {
  amb::fw::WearRecord r;
  r.sequence = seq;
  r.board_name = "bath-amb-rig";
  r.life_model = "link-test";
  r.event_count = seq;
  r.bearing[0].life_used_fraction = 0.01f * static_cast<float>(seq);
  r.bearing[1].peak_force_n = 1234.0f;
  return r;
}

TEST(Link, ListAndDownloadEventsWithEndToEndCrc) {
  const std::string dir = temp_dir("dl");
  Board b(dir);
  std::string err;
  const auto e1 = blob(100000, 1), e2 = blob(5, 2);
  ASSERT_TRUE(b.events->write_atomic("drop-0001.evt", e1, err));
  ASSERT_TRUE(b.events->write_atomic("drop-0002.evt", e2, err));
  lk::ModbusLink link(b.link());
  const auto id = lk::read_identity(link);
  EXPECT_EQ(id.board_name, "bath-amb-rig");
  const auto list = lk::list_events(link);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].name, "drop-0001.evt");
  EXPECT_EQ(list[0].crc32, amb::fw::crc32c(e1));
  std::vector<uint8_t> got;
  lk::TransferStats s;
  lk::download(link, list[0].index, list[0].crc32, list[0].size, got, s);
  EXPECT_EQ(got, e1);
  const double kib_s = static_cast<double>(s.bytes) / 1024.0 / s.wall_s;
  std::printf("[ figures ] event download over Modbus TCP loopback: %llu bytes in %.3f s = %.1f KiB/s (%llu requests)\n",
              static_cast<unsigned long long>(s.bytes), s.wall_s, kib_s, static_cast<unsigned long long>(s.requests));
  EXPECT_GT(kib_s, 50.0);
  got.clear();
  lk::download(link, list[1].index, list[1].crc32, list[1].size, got, s);
  EXPECT_EQ(got, e2);
  // The item changes on the board between listing and download: refused as stale.
  ASSERT_TRUE(b.events->write_atomic("drop-0002.evt", blob(5, 3), err));
  got.clear();
  EXPECT_THROW(lk::download(link, list[1].index, list[1].crc32, list[1].size, got, s), std::runtime_error);
  std::filesystem::remove_all(dir);
}

TEST(Link, DownloadResumesAfterDroppedConnectionsAndFromPartialData) {
  const std::string dir = temp_dir("resume");
  Board b(dir);
  std::string err;
  const auto e = blob(60000, 4);
  ASSERT_TRUE(b.events->write_atomic("drop-0003.evt", e, err));
  // Every connection through the proxy is cut after ~1 KB of requests.
  amb::test::FlakyProxy proxy(b.server->bound_port(), 1000);
  lk::ModbusLink link(b.link(proxy.port()));
  const auto list = lk::list_events(link);
  ASSERT_EQ(list.size(), 1u);
  std::vector<uint8_t> got;
  lk::TransferStats s;
  lk::download(link, 0, list[0].crc32, list[0].size, got, s);
  EXPECT_EQ(got, e);
  EXPECT_GT(proxy.cuts(), 3);
  EXPECT_GT(s.reconnects, 3);
  std::printf("[ figures ] download through a proxy cutting every ~1 KB: %d reconnects, %.3f s\n", s.reconnects, s.wall_s);
  // Resume from a partial file: only the rest is transferred.
  std::vector<uint8_t> partial(e.begin(), e.begin() + 25000);
  lk::TransferStats s2;
  lk::ModbusLink direct(b.link());
  lk::download(direct, 0, list[0].crc32, list[0].size, partial, s2);
  EXPECT_EQ(partial, e);
  EXPECT_EQ(s2.resumed_from, 25000u / amb::fw::regs::k_block_bytes * amb::fw::regs::k_block_bytes);
  EXPECT_LT(s2.bytes, 36000u);
  std::filesystem::remove_all(dir);
}

TEST(Link, WriteBackIsValidatedPersistedAndSurvivesRestart) {
  const std::string dir = temp_dir("wb");
  {
    Board b(dir);
    lk::ModbusLink link(b.link());
    auto o = lk::write_back(link, amb::fw::encode_wear_record(record(1)), k_arm_key);
    EXPECT_EQ(o.result_name, "accepted");
    // The very same record again: the board already holds it (nothing is written).
    o = lk::write_back(link, amb::fw::encode_wear_record(record(1)), k_arm_key);
    EXPECT_EQ(o.result_name, "already_stored");
    // A different record with an old sequence, and a foreign record, are refused by the board.
    auto stale = record(1);
    stale.event_count = 77;
    o = lk::write_back(link, amb::fw::encode_wear_record(stale), k_arm_key);
    EXPECT_EQ(o.result_name, "stale_sequence");
    auto other = record(2);
    other.board_name = "unicamp-amb-rig";
    o = lk::write_back(link, amb::fw::encode_wear_record(other), k_arm_key);
    EXPECT_EQ(o.result_name, "wrong_board");
    // Through a connection cut every ~2 KiB: resumed, accepted.
    amb::test::FlakyProxy proxy(b.server->bound_port(), 2000);
    lk::ModbusLink flaky(b.link(proxy.port()));
    o = lk::write_back(flaky, amb::fw::encode_wear_record(record(2)), k_arm_key);
    EXPECT_EQ(o.result_name, "accepted");
    EXPECT_GT(proxy.cuts(), 1);
    const auto w = lk::read_wear_summary(link);
    EXPECT_EQ(w.sequence, 2u);
    EXPECT_EQ(w.crc32, amb::fw::crc32c(amb::fw::encode_wear_record(record(2))));
  }
  // "Power cycle": a new board process on the same storage serves the same record.
  Board again(dir);
  lk::ModbusLink link(again.link());
  const auto w = lk::read_wear_summary(link);
  EXPECT_TRUE(w.present);
  EXPECT_EQ(w.sequence, 2u);
  EXPECT_EQ(w.corrupt_at_start, 0);
  std::vector<uint8_t> rec;
  lk::TransferStats s;
  lk::download(link, amb::fw::regs::k_wear_item_index, w.crc32, static_cast<uint32_t>(amb::fw::wear_record_size()), rec, s);
  EXPECT_EQ(rec, amb::fw::encode_wear_record(record(2)));
  std::filesystem::remove_all(dir);
}

// The commit is a command: without the right key it is refused before anything is written;
// a commit that fails in the board's storage (EIO on fsync) keeps the old record, is counted,
// and is armed and committed again by the host once the storage recovers.
TEST(Link, WriteBackNeedsTheArmKeyAndSurvivesAStorageFailure) {
  const std::string dir = temp_dir("wbfault");
  {
    Board b(dir);
    lk::ModbusLink link(b.link());
    ASSERT_EQ(lk::write_back(link, amb::fw::encode_wear_record(record(1)), k_arm_key).result_name, "accepted");
    try {
      lk::write_back(link, amb::fw::encode_wear_record(record(2)), k_arm_key ^ 1);
      ADD_FAILURE() << "a wrong arm key was accepted";
    } catch (const lk::ModbusException& e) {
      EXPECT_EQ(e.code(), 3);
      EXPECT_NE(std::string(e.what()).find("wrong arm key"), std::string::npos) << e.what();
    }
    EXPECT_EQ(lk::read_wear_summary(link).sequence, 1u);
    // Storage fails every fsync: the board answers exception 4 (storage_failed), keeps record 1.
    struct FailFsync final : amb::hal::linux_hw::FsFaultHook {
      int before(amb::hal::linux_hw::FsOp op, std::string_view, uint64_t) override {
        return op == amb::hal::linux_hw::FsOp::fsync ? EIO : 0;
      }
    } eio;
    b.wear_fs->set_fault_hook(&eio);
    auto o = lk::write_back(link, amb::fw::encode_wear_record(record(2)), k_arm_key);
    EXPECT_EQ(o.result_name, "storage_failed");
    EXPECT_EQ(o.commit_attempts, 3);
    EXPECT_EQ(lk::read_wear_summary(link).sequence, 1u);
    uint16_t r[18];
    lk::ModbusLink raw(b.link());
    raw.read(amb::fw::regs::storage_stats, std::span<uint16_t>(r, 18));
    EXPECT_EQ(lk::u32_at(std::span<const uint16_t>(r, 18), 16), 3u) << "wear-record commits failed in storage";
    b.wear_fs->set_fault_hook(nullptr);
    o = lk::write_back(link, amb::fw::encode_wear_record(record(2)), k_arm_key);
    EXPECT_EQ(o.result_name, "accepted");
    EXPECT_EQ(o.stats.bytes, 0u) << "the complete session was kept: only the commit was repeated";
  }
  Board again(dir);
  lk::ModbusLink link(again.link());
  const auto w = lk::read_wear_summary(link);
  EXPECT_EQ(w.sequence, 2u);
  EXPECT_EQ(w.corrupt_at_start, 0) << "no torn slot after the failed commits";
  std::filesystem::remove_all(dir);
}

}  // namespace
