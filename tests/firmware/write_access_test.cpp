// Write access of the supervisory register map (docs/register-map.md, "Write access"): every
// command register — the command register (levitate, run, land, reset fault, emergency stop,
// manual capture), event delete and the wear-record commit — is refused without the arm
// sequence (exception 1), with a wrong key (3, then 1), with an arm for another operation,
// after the arm window, on a second use of one arm, and in every lifecycle state where the
// command does not apply (6). A refused command changes nothing: the loop's state stays, no
// command is pending, the event and the wear record stay. Accepted commands are counted.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "boards/embedded_boards.hpp"
#include "firmware/board/board.hpp"
#include "firmware/persistence/crc32c.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "firmware/wear/wear_record.hpp"
#include "hal/sim/sim_rig.hpp"
#include "tests/firmware/register_stores.hpp"

namespace {

namespace regs = amb::fw::regs;
using amb::fw::Phase;
using amb::fw::State;
using St = amb::hal::RegisterHandler::Status;

constexpr uint32_t k_key = 0xA5C3'1F07;
constexpr int64_t k_window_ns = 2'000'000'000;

/// Where the fixture puts the loop before the command is tried.
enum class Where { unconfigured, inactive, lifting, levitated, running, fault };
const char* name(Where w) {
  switch (w) {
    case Where::unconfigured: return "unconfigured";
    case Where::inactive: return "inactive";
    case Where::lifting: return "levitating/lifting";
    case Where::levitated: return "levitating/levitated";
    case Where::running: return "running";
    case Where::fault: return "fault";
  }
  return "?";
}

/// The operations and the lifecycle states where each applies (the table in docs/register-map.md).
struct Op {
  uint16_t code;
  const char* label;
  std::vector<Where> allowed;
};
const std::vector<Op>& ops() {
  static const std::vector<Op> v{
      {regs::op_levitate, "levitate", {Where::inactive}},
      {regs::op_run, "run", {Where::levitated}},
      {regs::op_land, "land", {Where::lifting, Where::levitated, Where::running}},
      {regs::op_reset_fault, "reset fault", {Where::fault}},
      {regs::op_emergency_stop, "emergency stop", {Where::lifting, Where::levitated, Where::running}},
      {regs::op_capture, "manual capture", {Where::inactive, Where::lifting, Where::levitated, Where::running, Where::fault}},
      {regs::op_event_delete, "event delete", {Where::unconfigured, Where::inactive, Where::fault}},
      {regs::op_wear_commit, "wear-record commit", {Where::unconfigured, Where::inactive, Where::fault}},
  };
  return v;
}

struct Fixture : amb::test::MemoryStores {
  amb::board::BoardConfig board = amb::board::load_board("bath-amb-rig");
  amb::fw::Supervisor sup;
  std::unique_ptr<amb::fw::RegisterMap> map;
  int64_t t_ns = 1'000'000'000;
  int captures = 0;
  std::vector<uint8_t> event = std::vector<uint8_t>(500, 0x3C);
  std::vector<uint8_t> record;

  explicit Fixture(Where w) : MemoryStores("bath-amb-rig") {
    std::string err;
    events.write_atomic("event_00000001.ambe", event, err);
    wear.open();
    amb::fw::WearRecord r;
    r.sequence = 1;
    r.board_name = "bath-amb-rig";
    r.life_model = "write-access-test";
    record = amb::fw::encode_wear_record(r);
    if (w != Where::unconfigured) sup.configure(board);
    amb::fw::RegisterSources src = amb::test::board_sources(sup, *this, board);
    src.manual_capture = [this] { return ++captures, true; };
    src.now_ns = [this] { return t_ns; };
    src.arm_key = k_key;
    src.arm_window_ns = k_window_ns;
    map = std::make_unique<amb::fw::RegisterMap>(src);
    if (w == Where::unconfigured) return;
    step(1);
    if (w == Where::inactive) return;
    post(amb::fw::Command::levitate);
    step(1);
    if (w == Where::lifting) return;
    if (w == Where::fault) {
      post(amb::fw::Command::emergency_stop);
      step(1);
      return;
    }
    for (int i = 0; i < 200000 && sup.status().phase != Phase::levitated; ++i) step(1);
    if (w == Where::levitated) return;
    post(amb::fw::Command::run);
    step(1);
  }
  /// Loop periods with the rotor at the bearing centre (the plant is not needed here).
  void step(int n) {
    amb::hal::AnalogInputs in;
    amb::hal::AnalogOutputs out;
    amb::hal::DiscreteOutputs dout;
    for (int i = 0; i < n; ++i) sup.step(in, true, {}, out, dout);
  }
  void post(amb::fw::Command c) { ASSERT_TRUE(sup.post(c)); }
  St write(uint16_t address, std::vector<uint16_t> v) { return map->write_registers(address, v); }
  St arm(uint16_t op, uint32_t key = k_key) {
    return write(regs::arm, {static_cast<uint16_t>(key >> 16), static_cast<uint16_t>(key), op});
  }
  /// Stage the wear record as a complete write-back session (not a command: no arm needed).
  void stage_record() {
    const uint32_t crc = amb::fw::crc32c(record);
    const uint32_t n = static_cast<uint32_t>(record.size());
    ASSERT_EQ(write(regs::wb_control, {regs::wb_begin, static_cast<uint16_t>(n >> 16), static_cast<uint16_t>(n),
                                       static_cast<uint16_t>(crc >> 16), static_cast<uint16_t>(crc)}),
              St::ok);
    for (uint32_t at = 0; at < n; at += regs::k_chunk_bytes) {
      const uint32_t k = std::min<uint32_t>(regs::k_chunk_bytes, n - at);
      std::vector<uint16_t> c{static_cast<uint16_t>(at >> 16), static_cast<uint16_t>(at), static_cast<uint16_t>(k)};
      for (uint32_t i = 0; i < k; i += 2)
        c.push_back(static_cast<uint16_t>(record[at + i] << 8 | (i + 1 < k ? record[at + i + 1] : 0)));
      ASSERT_EQ(write(regs::wb_chunk, c), St::ok);
    }
  }
  /// The command write of operation `op` (its register and value).
  St command(uint16_t op) {
    switch (op) {
      case regs::op_event_delete: {
        const uint32_t crc = amb::fw::crc32c(event);
        return write(regs::event_delete, {0, static_cast<uint16_t>(crc >> 16), static_cast<uint16_t>(crc)});
      }
      case regs::op_wear_commit: return write(regs::wb_control, {regs::wb_commit});
      default: return write(regs::command, {op});
    }
  }
  /// Whether the command had an effect: a command pending in the loop, a capture requested,
  /// the event gone, the wear record stored.
  bool something_happened() {
    const bool pending = !sup.post(amb::fw::Command::none);  // post() fails while one is pending
    return pending || captures > 0 || events.list().empty() || wear.has_record();
  }
  std::vector<uint16_t> read(uint16_t address, size_t n) {
    std::vector<uint16_t> r(n);
    EXPECT_EQ(map->read_registers(address, r), St::ok);
    return r;
  }
};

uint32_t u32(const std::vector<uint16_t>& r, size_t at) { return static_cast<uint32_t>(r[at]) << 16 | r[at + 1]; }

const std::vector<Where> k_states{Where::unconfigured, Where::inactive, Where::lifting,
                                  Where::levitated,    Where::running,  Where::fault};

TEST(WriteAccess, EveryCommandIsRefusedWithoutTheArmSequenceInEveryState) {
  for (Where w : k_states)
    for (const Op& op : ops()) {
      SCOPED_TRACE(std::string(op.label) + " in state " + name(w));
      Fixture fx(w);
      if (op.code == regs::op_wear_commit) fx.stage_record();
      const State before = fx.sup.status().state;
      // No arm at all.
      EXPECT_EQ(fx.command(op.code), St::illegal_function);
      // A wrong key is refused (3) and arms nothing.
      EXPECT_EQ(fx.arm(op.code, k_key ^ 0x0100), St::illegal_value);
      EXPECT_EQ(fx.command(op.code), St::illegal_function);
      // An arm for another operation does not arm this one (and is left for its own operation).
      const uint16_t other = op.code == regs::op_levitate ? regs::op_land : regs::op_levitate;
      ASSERT_EQ(fx.arm(other), St::ok);
      EXPECT_EQ(fx.command(op.code), St::illegal_function);
      EXPECT_EQ(fx.read(regs::arm, 1)[0], other) << "a stray write does not cancel another operation's arm";
      // An arm that expired.
      ASSERT_EQ(fx.arm(op.code), St::ok);
      fx.t_ns += k_window_ns + 1;
      EXPECT_EQ(fx.command(op.code), St::illegal_function);
      fx.step(fx.sup.status().state == State::unconfigured ? 0 : 3);
      EXPECT_EQ(fx.sup.status().state, before);
      EXPECT_FALSE(fx.something_happened());
      const auto a = fx.read(regs::access_stats, 14);
      EXPECT_EQ(u32(a, 0), 2u) << "arms accepted";
      EXPECT_EQ(u32(a, 2), 1u) << "arm key mismatches";
      EXPECT_EQ(u32(a, 4), 0u) << "commands accepted";
      EXPECT_EQ(u32(a, 6), 4u) << "refused: not armed";
    }
}

TEST(WriteAccess, ArmedCommandsAreRefusedInTheWrongStateAndTakenInTheRightOne) {
  int accepted = 0, refused = 0;
  for (Where w : k_states)
    for (const Op& op : ops()) {
      SCOPED_TRACE(std::string(op.label) + " in state " + name(w));
      Fixture fx(w);
      if (op.code == regs::op_wear_commit) fx.stage_record();
      const bool allowed = std::find(op.allowed.begin(), op.allowed.end(), w) != op.allowed.end();
      ASSERT_EQ(fx.arm(op.code), St::ok);
      const auto armed = fx.read(regs::arm, 2);
      EXPECT_EQ(armed[0], op.code);
      EXPECT_EQ(armed[1], k_window_ns / 1'000'000) << "ms left";
      fx.t_ns += k_window_ns / 2;  // within the window
      const St st = fx.command(op.code);
      const auto a = fx.read(regs::access_stats, 14);
      if (allowed) {
        EXPECT_EQ(st, St::ok);
        EXPECT_TRUE(fx.something_happened());
        EXPECT_EQ(u32(a, 4), 1u) << "commands accepted";
        ++accepted;
      } else {
        EXPECT_EQ(st, St::busy) << "exception 6 in the wrong state";
        EXPECT_FALSE(fx.something_happened());
        EXPECT_EQ(u32(a, 8), 1u) << "refused: wrong state";
        EXPECT_EQ(u32(fx.read(regs::modbus_stats, 14), 10), 1u) << "0x052A refused (state)";
        ++refused;
      }
      // Single use: the same write again without a new arm is refused.
      EXPECT_EQ(fx.command(op.code), St::illegal_function);
    }
  std::printf("[ figures ] %d (operation, state) pairs accepted with the arm, %d refused in the wrong state\n",
              accepted, refused);
  EXPECT_EQ(accepted, 20);
  EXPECT_EQ(refused, 28);
}

TEST(WriteAccess, ArmedCommandsMoveTheLoop) {
  Fixture fx(Where::inactive);
  ASSERT_EQ(fx.arm(regs::op_levitate), St::ok);
  ASSERT_EQ(fx.command(regs::op_levitate), St::ok);
  fx.step(2);
  EXPECT_EQ(fx.sup.status().state, State::levitating);
  EXPECT_EQ(fx.read(regs::command, 1)[0], 1) << "posted";
}

TEST(WriteAccess, BadValuesAndLengthsAreRefusedAndCountedAndLeaveTheArm) {
  Fixture fx(Where::inactive);
  ASSERT_EQ(fx.arm(regs::op_levitate), St::ok);
  EXPECT_EQ(fx.write(regs::command, {99}), St::illegal_value);
  EXPECT_EQ(fx.arm(regs::op_levitate, k_key + 1), St::illegal_value) << "a wrong key";
  EXPECT_EQ(fx.read(regs::arm, 1)[0], regs::op_levitate) << "refused writes leave the arm in place";
  EXPECT_EQ(fx.command(regs::op_levitate), St::ok);
  EXPECT_EQ(fx.command(regs::op_levitate), St::illegal_function) << "used once";
  EXPECT_EQ(fx.write(regs::arm, {0, 1}), St::illegal_value) << "arm needs 3 registers";
  EXPECT_EQ(fx.arm(9), St::illegal_value) << "no operation 9 (7, 8: sweep start, abort)";
  EXPECT_EQ(fx.arm(0), St::illegal_value);
  EXPECT_EQ(fx.write(regs::command, {1, 1}), St::illegal_value);
  EXPECT_EQ(fx.write(regs::event_delete, {0}), St::illegal_value);
  EXPECT_EQ(fx.write(regs::wb_control, {regs::wb_commit, 0}), St::illegal_value);
  // The key is never served.
  ASSERT_EQ(fx.arm(regs::op_levitate), St::ok);
  const auto r = fx.read(regs::arm, 3);
  EXPECT_EQ(r[0], regs::op_levitate);
  EXPECT_EQ(r[2], 0);
  const auto a = fx.read(regs::access_stats, 14);
  EXPECT_EQ(u32(a, 10), 8u) << "writes refused for a bad value (the wrong key too)";
}

TEST(WriteAccess, ABoardWithoutAnArmKeyTakesNoCommands) {
  const auto board = amb::board::load_board("bath-amb-rig");
  EXPECT_EQ(board.comms.modbus.arm_key, 0u) << "the default: no key";
  EXPECT_EQ(board.comms.modbus.bind_address, "127.0.0.1") << "the default: loopback only";
  amb::fw::Supervisor sup;
  sup.configure(board);
  amb::fw::RegisterSources src;
  src.supervisor = &sup;
  amb::fw::RegisterMap map(src);
  const std::vector<uint16_t> arm{0, 0, regs::op_levitate};
  EXPECT_EQ(map.write_registers(regs::arm, arm), St::illegal_function);
  const std::vector<uint16_t> cmd{regs::op_levitate};
  EXPECT_EQ(map.write_registers(regs::command, cmd), St::illegal_function);
  EXPECT_TRUE(sup.post(amb::fw::Command::none));
}

TEST(WriteAccess, ArmKeyAndWindowComeFromTheBoardFile) {
  auto text = [](const std::string& modbus) {
    return std::string("[comms]\ndata_dir = \"/tmp/x\"\n[comms.modbus]\n") + modbus;
  };
  std::string bath;
  for (const auto* e = amb::boards::embedded_boards(); e->name; ++e)
    if (std::string(e->name) == "bath-amb-rig") bath = e->toml;
  ASSERT_FALSE(bath.empty());
  auto board = [&](const std::string& modbus) { return amb::board::parse_board(bath + "\n" + text(modbus), "test.toml"); };
  const auto b = board("arm_key = 0x5EC0DE42\narm_window_ms = 1500\nmax_clients = 2\n");
  EXPECT_EQ(b.comms.modbus.arm_key, 0x5EC0DE42u);
  EXPECT_EQ(b.comms.modbus.arm_window_ms, 1500u);
  EXPECT_EQ(b.comms.modbus.max_clients, 2);
  EXPECT_EQ(b.comms.modbus.bind_address, "127.0.0.1");
  EXPECT_THROW(board("arm_key = 0\n"), std::exception);
  EXPECT_THROW(board("arm_key = 4294967296\n"), std::exception);
  EXPECT_THROW(board("arm_window_ms = 50\n"), std::exception);
}

}  // namespace
