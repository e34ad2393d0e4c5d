// The register map served by the real libmodbus TCP server on 127.0.0.1 (ephemeral port),
// read and written by a real libmodbus client: identity, state, access rules (read-only,
// unknown addresses, bad values, unsafe writes while levitated), malformed frames counted
// and refused without disturbing a running loop.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "firmware/board/board.hpp"
#include "firmware/persistence/crc32c.hpp"
#include "firmware/sil/sil_rig.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/linux/modbus_tcp_server.hpp"
#include "hal/sim/sim_rig.hpp"
#include "tests/firmware/register_stores.hpp"

namespace {

namespace regs = amb::fw::regs;
using amb::hal::linux_hw::ModbusTcpServer;

constexpr uint32_t k_arm_key = 0x0BADF00D;

struct Fixture : amb::test::MemoryStores {
  amb::board::BoardConfig board = amb::board::load_board("bath-amb-rig");
  amb::fw::Supervisor sup;
  std::unique_ptr<amb::fw::RegisterMap> map;
  std::unique_ptr<ModbusTcpServer> server;

  Fixture() : MemoryStores("bath-amb-rig") {
    sup.configure(board);
    wear.open();
    amb::fw::RegisterSources src = amb::test::board_sources(sup, *this, board);
    src.arm_key = k_arm_key;
    src.link = [this] {
      const auto s = server->stats();
      return amb::fw::LinkCounters{s.requests, s.exceptions, s.bad_frames, s.wrong_unit, s.connections,
                                   s.refused_connections};
    };
    map = std::make_unique<amb::fw::RegisterMap>(src);
    amb::hal::linux_hw::ModbusTcpOptions o;
    o.bind_address = "127.0.0.1";
    o.port = 0;
    server = std::make_unique<ModbusTcpServer>(o);
    std::string err;
    if (!server->start(*map, err)) throw std::runtime_error(err);
  }
  modbus_t* client() const {
    modbus_t* c = modbus_new_tcp("127.0.0.1", server->bound_port());
    modbus_set_slave(c, 1);
    if (modbus_connect(c) != 0) throw std::runtime_error("connect failed");
    return c;
  }
  void step_rest(int n) {
    amb::hal::AnalogInputs in;
    amb::hal::AnalogOutputs out;
    amb::hal::DiscreteOutputs dout;
    for (int i = 0; i < n; ++i) sup.step(in, true, {}, out, dout);
  }
};

int exception_of(int rc) { return rc >= 0 ? 0 : errno - MODBUS_ENOBASE; }

/// The arm sequence over the wire: [key hi, key lo, operation] to 0x0F00 (function 16).
int arm(modbus_t* c, uint16_t op, uint32_t key = k_arm_key) {
  const uint16_t v[3] = {static_cast<uint16_t>(key >> 16), static_cast<uint16_t>(key), op};
  return modbus_write_registers(c, regs::arm, 3, v);
}

TEST(RegisterMap, IdentityAndStateOverModbusTcp) {
  Fixture fx;
  fx.step_rest(3);
  modbus_t* c = fx.client();
  uint16_t r[125];
  ASSERT_EQ(modbus_read_registers(c, regs::identity, regs::identity_end, r), regs::identity_end);
  EXPECT_EQ(r[regs::magic], regs::k_magic_value);
  EXPECT_EQ(r[regs::map_version], regs::k_map_version);
  EXPECT_EQ(r[regs::loop_rate_hz], 10000);
  EXPECT_EQ(r[regs::board_name], ('b' << 8) | 'a');
  // Function 4 reads the same registers.
  ASSERT_EQ(modbus_read_input_registers(c, regs::magic, 1, r), 1);
  EXPECT_EQ(r[0], regs::k_magic_value);
  ASSERT_EQ(modbus_read_registers(c, regs::state, 10, r), 10);
  EXPECT_EQ(r[0], static_cast<uint16_t>(amb::fw::State::inactive));
  EXPECT_EQ(r[7], 3);  // step count low word
  modbus_close(c);
  modbus_free(c);
}

TEST(RegisterMap, AccessRules) {
  Fixture fx;
  fx.step_rest(1);
  modbus_t* c = fx.client();
  uint16_t r[125];
  // Unknown address, a read straddling into a hole, and writes to read-only registers.
  EXPECT_EQ(exception_of(modbus_read_registers(c, 0x7000, 1, r)), MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
  EXPECT_EQ(exception_of(modbus_read_registers(c, regs::identity_end - 1, 4, r)), MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::state, 1)), MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::wear_sequence, 9)), MODBUS_EXCEPTION_ILLEGAL_DATA_ADDRESS);
  // Functions not served: coils, discrete inputs.
  uint8_t bits[8];
  EXPECT_EQ(exception_of(modbus_read_bits(c, 0, 8, bits)), MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
  EXPECT_EQ(exception_of(modbus_write_bit(c, 0, 1)), MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
  // Bad values.
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::command, 99)), MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
  const uint16_t bad_begin[5] = {regs::wb_begin, 0xFFFF, 0xFFFF, 0, 0};
  EXPECT_EQ(exception_of(modbus_write_registers(c, regs::wb_control, 5, bad_begin)), MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
  // A command without the arm sequence: exception 1, nothing happens; with a wrong key: 3.
  const uint16_t lev = static_cast<uint16_t>(amb::fw::Command::levitate);
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::command, lev)), MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
  EXPECT_EQ(exception_of(arm(c, regs::op_levitate, k_arm_key + 1)), MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::command, lev)), MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
  fx.step_rest(2);
  ASSERT_EQ(fx.sup.state(), amb::fw::State::inactive);
  // Armed: levitate; then the unsafe writes, armed too, are refused with "busy" (wrong state).
  ASSERT_EQ(arm(c, regs::op_levitate), 3);
  ASSERT_EQ(modbus_write_register(c, regs::command, lev), 1);
  fx.step_rest(2);
  ASSERT_EQ(fx.sup.state(), amb::fw::State::levitating);
  ASSERT_EQ(modbus_read_registers(c, regs::state_flags, 1, r), 1);
  EXPECT_EQ(r[0] & 1, 1);
  ASSERT_EQ(arm(c, regs::op_wear_commit), 3);
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::wb_control, regs::wb_commit)), MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY);
  const uint16_t del[3] = {0, 0, 0};
  ASSERT_EQ(arm(c, regs::op_event_delete), 3);
  EXPECT_EQ(exception_of(modbus_write_registers(c, regs::event_delete, 3, del)), MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY);
  // Levitate again while levitating: wrong state.
  ASSERT_EQ(arm(c, regs::op_levitate), 3);
  EXPECT_EQ(exception_of(modbus_write_register(c, regs::command, lev)), MODBUS_EXCEPTION_SLAVE_OR_SERVER_BUSY);
  ASSERT_EQ(modbus_read_registers(c, regs::modbus_stats, 14, r), 14);
  EXPECT_EQ((static_cast<uint32_t>(r[10]) << 16) | r[11], 3u);  // refused in the wrong state
  EXPECT_GE((static_cast<uint32_t>(r[2]) << 16) | r[3], 13u);    // exceptions
  ASSERT_EQ(modbus_read_registers(c, regs::access_stats, 14, r), 14);
  EXPECT_EQ((static_cast<uint32_t>(r[0]) << 16) | r[1], 4u);    // arms accepted
  EXPECT_EQ((static_cast<uint32_t>(r[2]) << 16) | r[3], 1u);    // wrong key
  EXPECT_EQ((static_cast<uint32_t>(r[4]) << 16) | r[5], 1u);    // commands accepted
  EXPECT_EQ((static_cast<uint32_t>(r[6]) << 16) | r[7], 2u);    // refused, not armed
  modbus_close(c);
  modbus_free(c);
}

// Raw bytes on the socket: garbage, a wrong protocol id, a length field that lies, a request
// to another unit. Each is counted; the server keeps serving well-formed clients.
TEST(RegisterMap, MalformedFramesAreCountedAndRefused) {
  Fixture fx;
  auto raw = [&](std::vector<uint8_t> bytes) {
    const int s = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(fx.server->bound_port());
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    EXPECT_EQ(::send(s, bytes.data(), bytes.size(), 0), static_cast<ssize_t>(bytes.size()));
    uint8_t reply[300];
    timeval tv{2, 0};
    setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    const ssize_t n = ::recv(s, reply, sizeof reply, 0);
    ::close(s);
    return n > 0 ? std::vector<uint8_t>(reply, reply + n) : std::vector<uint8_t>{};
  };
  // Wrong protocol id (0x1234): connection closed without an answer.
  EXPECT_TRUE(raw({0, 1, 0x12, 0x34, 0, 6, 1, 3, 0, 0, 0, 1}).empty());
  // Length field says 20 bytes, 6 follow (the rest never comes: request timeout, closed).
  EXPECT_TRUE(raw({0, 2, 0, 0, 0, 20, 1, 3, 0, 0, 0, 1}).empty());
  // Wrong unit id: exception 0x0B (gateway target failed to respond).
  auto rep = raw({0, 3, 0, 0, 0, 6, 77, 3, 0, 0, 0, 1});
  ASSERT_EQ(rep.size(), 9u);
  EXPECT_EQ(rep[7], 0x83);
  EXPECT_EQ(rep[8], 0x0B);
  // Read of 200 registers: exception 3.
  rep = raw({0, 4, 0, 0, 0, 6, 1, 3, 0, 0, 0, 200});
  ASSERT_EQ(rep.size(), 9u);
  EXPECT_EQ(rep[8], MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
  // Write-multiple whose byte count (2) disagrees with its register count (2 -> 4 bytes).
  rep = raw({0, 5, 0, 0, 0, 9, 1, 16, 0x10, 0x00, 0, 2, 2, 0, 1});
  ASSERT_EQ(rep.size(), 9u);
  EXPECT_EQ(rep[8], MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
  const auto st = fx.server->stats();
  EXPECT_GE(st.bad_frames, 2u);
  EXPECT_EQ(st.wrong_unit, 1u);
  // Still serving.
  modbus_t* c = fx.client();
  uint16_t r[1];
  EXPECT_EQ(modbus_read_registers(c, regs::magic, 1, r), 1);
  modbus_close(c);
  modbus_free(c);
}

// A client that sends part of a request and waits (slow or hostile) does not hold up the
// others: the server never waits on one connection; the partial request is dropped after
// request_timeout_ms (1 s), counted as a bad frame.
TEST(RegisterMap, ASlowClientDoesNotHoldUpTheOthers) {
  Fixture fx;
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(fx.server->bound_port());
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  const uint8_t partial[] = {0, 9, 0, 0, 0, 6, 1, 3};  // 8 of 12 bytes
  ASSERT_EQ(::send(s, partial, sizeof partial, 0), static_cast<ssize_t>(sizeof partial));
  modbus_t* c = fx.client();
  uint16_t r[1];
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 20; ++i) ASSERT_EQ(modbus_read_registers(c, regs::magic, 1, r), 1);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(ms, 500.0) << "20 requests while another client holds a partial frame";
  std::printf("[ figures ] 20 requests in %.1f ms while another client held a partial frame\n", ms);
  // The slow client is closed after the request timeout.
  timeval tv{3, 0};
  setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  uint8_t buf[16];
  EXPECT_EQ(::recv(s, buf, sizeof buf, 0), 0) << "closed by the server";
  ::close(s);
  EXPECT_EQ(fx.server->stats().bad_frames, 1u);
  modbus_close(c);
  modbus_free(c);
}

TEST(RegisterMap, EventListAndDownloadWindow) {
  Fixture fx;
  std::string err;
  std::vector<uint8_t> ev(1000);
  for (size_t i = 0; i < ev.size(); ++i) ev[i] = static_cast<uint8_t>(i * 7);
  ASSERT_TRUE(fx.events.write_atomic("event-0001.bin", ev, err));
  modbus_t* c = fx.client();
  uint16_t r[125];
  ASSERT_EQ(modbus_read_registers(c, regs::event_count, 23, r), 23);
  EXPECT_EQ(r[0], 1);
  const uint32_t crc = (static_cast<uint32_t>(r[5]) << 16) | r[6];
  EXPECT_EQ(crc, amb::fw::crc32c(ev));
  EXPECT_EQ((static_cast<uint32_t>(r[3]) << 16) | r[4], 1000u);
  // Block 4 (bytes 912..999) with function 23: select and read in one transaction.
  const uint16_t sel[5] = {0, static_cast<uint16_t>(crc >> 16), static_cast<uint16_t>(crc), 0, 4};
  const int n = regs::dl_end - regs::dl_status;
  ASSERT_EQ(modbus_write_and_read_registers(c, regs::dl_select, 5, sel, regs::dl_status, n, r), n);
  EXPECT_EQ(r[0], regs::dl_ok);
  EXPECT_EQ(r[1], 1000 - 4 * regs::k_block_bytes);
  EXPECT_EQ(r[regs::dl_data - regs::dl_status] >> 8, ev[4 * regs::k_block_bytes]);
  // A stale CRC is refused in the status.
  const uint16_t stale[5] = {0, 1, 2, 0, 0};
  ASSERT_EQ(modbus_write_and_read_registers(c, regs::dl_select, 5, stale, regs::dl_status, 1, r), 1);
  EXPECT_EQ(r[0], regs::dl_stale);
  modbus_close(c);
  modbus_free(c);
}

// Clients hammering the server with bad requests do not disturb the loop: the server thread
// touches the loop only through lock-free snapshots and Supervisor::post. The same SIL run
// (deterministic: same board, same noise seed) with and without the hammering must end in a
// bit-identical state.
amb::fw::Status run_sil(const amb::board::BoardConfig& board, bool hammer_it, uint64_t& exceptions) {
  amb::sil::SilRig rig(board);
  amb::fw::RegisterSources src;
  src.supervisor = &rig.supervisor();
  src.board_name = board.name;
  amb::fw::RegisterMap map(src);
  amb::hal::linux_hw::ModbusTcpOptions o;
  o.bind_address = "127.0.0.1";
  o.port = 0;
  ModbusTcpServer server(o);
  std::string err;
  if (!server.start(map, err)) throw std::runtime_error(err);
  std::atomic<bool> done{false};
  std::thread hammer;
  if (hammer_it)
    hammer = std::thread([&] {
      modbus_t* c = modbus_new_tcp("127.0.0.1", server.bound_port());
      modbus_connect(c);
      uint16_t r[125];
      while (!done) {
        modbus_read_registers(c, 0x7777, 10, r);     // unknown address
        modbus_write_register(c, regs::state, 0);    // read-only
        modbus_write_register(c, regs::command, 200);// bad value
        modbus_read_registers(c, regs::state, 10, r);
      }
      modbus_close(c);
      modbus_free(c);
    });
  rig.supervisor().post(amb::fw::Command::levitate);
  rig.loop().run_periods(5000);
  done = true;
  if (hammer.joinable()) hammer.join();
  server.stop();
  exceptions = server.stats().exceptions;
  return rig.supervisor().status();
}

TEST(RegisterMap, BadRequestsDoNotDisturbTheLoop) {
  const auto board = amb::board::load_board("bath-amb-rig");
  uint64_t quiet_exceptions = 0, busy_exceptions = 0;
  const amb::fw::Status quiet = run_sil(board, false, quiet_exceptions);
  const amb::fw::Status busy = run_sil(board, true, busy_exceptions);
  EXPECT_EQ(quiet.step, 5000u);
  EXPECT_EQ(busy.step, quiet.step);
  EXPECT_EQ(busy.state, quiet.state);
  EXPECT_EQ(busy.fault, quiet.fault);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(busy.xy_m[i], quiet.xy_m[i]) << i;  // bit-identical
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(busy.current_demand_a[i], quiet.current_demand_a[i]) << i;
  EXPECT_EQ(quiet_exceptions, 0u);
  EXPECT_GT(busy_exceptions, 10u);
  std::printf("[ figures ] %llu bad Modbus requests refused during 5000 loop periods, loop unchanged\n",
              static_cast<unsigned long long>(busy_exceptions));
}

}  // namespace
