// Field-bus protocol: codec round trips, refusal of malformed frames (fuzz), node-timeout
// safe state, and no allocation in the board side's read/write.
#define AMB_DEFINE_ALLOC_COUNTER
#include "tests/firmware/alloc_counter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

#include "firmware/board/board.hpp"
#include "firmware/fieldbus/field_bus_front_end.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "hal/sim/sim_rig.hpp"

namespace {

namespace fb = amb::fieldbus;
using amb::hal::CanFrame;

const fb::NodeIds k_ids{1, 2, 3};

TEST(FieldBusCodec, RoundTripsEveryMessage) {
  fb::Message m;
  const std::array<double, 4> d{12.3e-6, -250.0e-6, 0.0, 3.2e-3};
  ASSERT_EQ(fb::decode(fb::encode_position(2, d, 0), k_ids, fb::Side::board, m), fb::DecodeResult::ok);
  EXPECT_EQ(m.kind, fb::Kind::position);
  for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(m.displacement_m[i], d[i], 0.05e-6);

  const std::array<double, 4> c{1.234, -2.5, 0.0, 0.001};
  ASSERT_EQ(fb::decode(fb::encode_current(3, c, 0b0100), k_ids, fb::Side::board, m), fb::DecodeResult::ok);
  EXPECT_EQ(m.fault_bits, 0b0100u);
  EXPECT_TRUE(std::isnan(m.current_a[2]));
  EXPECT_NEAR(m.current_a[1], -2.5, 1e-3);

  ASSERT_EQ(fb::decode(fb::encode_demand(3, c), k_ids, fb::Side::nodes, m), fb::DecodeResult::ok);
  EXPECT_NEAR(m.current_a[0], 1.234, 1e-3);
  ASSERT_EQ(fb::decode(fb::encode_drive(3, 7, true, 45.125), k_ids, fb::Side::nodes, m), fb::DecodeResult::ok);
  EXPECT_EQ(m.flags, fb::drive_amplifiers_enabled);
  EXPECT_NEAR(m.speed_hz, 45.125, 1e-3);
  ASSERT_EQ(fb::decode(fb::encode_amp_status(3, 9, fb::amp_enabled | fb::amp_fault, 48.2, 41.5, 0x21), k_ids,
                       fb::Side::board, m),
            fb::DecodeResult::ok);
  EXPECT_EQ(m.flags, fb::amp_enabled | fb::amp_fault);
  EXPECT_NEAR(m.dc_bus_v, 48.2, 0.05);
  EXPECT_NEAR(m.temperature_c, 41.5, 0.05);
  EXPECT_EQ(m.amp_fault_code, 0x21);

  ASSERT_EQ(fb::decode(fb::encode_sample_fd(2, 513, d, c, 44.5, 0), k_ids, fb::Side::board, m), fb::DecodeResult::ok);
  EXPECT_EQ(m.sequence, 513);
  for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(m.displacement_m[i], d[i], 1e-9);
  EXPECT_NEAR(m.speed_hz, 44.5, 1e-3);
  ASSERT_EQ(fb::decode(fb::encode_demand_fd(3, 2, false, 10.0, c), k_ids, fb::Side::nodes, m), fb::DecodeResult::ok);
  EXPECT_NEAR(m.current_a[3], 0.001, 1e-6);
  ASSERT_EQ(fb::decode(fb::encode_heartbeat(2, fb::nmt_operational, 0), k_ids, fb::Side::board, m), fb::DecodeResult::ok);
  EXPECT_EQ(m.kind, fb::Kind::heartbeat);
  // Saturation instead of wrap-around.
  ASSERT_EQ(fb::decode(fb::encode_position(2, {1.0, -1.0, 0, 0}, 0), k_ids, fb::Side::board, m), fb::DecodeResult::ok);
  EXPECT_NEAR(m.displacement_m[0], 32767 * fb::k_position_lsb_m, 1e-12);
  EXPECT_NEAR(m.displacement_m[1], -32767 * fb::k_position_lsb_m, 1e-12);
}

TEST(FieldBusCodec, RefusesMalformedFrames) {
  fb::Message m;
  CanFrame f = fb::encode_position(2, {}, 0);
  f.len = 7;
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::board, m), fb::DecodeResult::malformed);
  f = fb::encode_position(2, {}, 0);
  f.fd = true;
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::board, m), fb::DecodeResult::malformed);
  f = fb::encode_amp_status(3, 0, 0, 0, 0, 0);
  f.data[0] = 0x80;  // reserved flag bit
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::board, m), fb::DecodeResult::malformed);
  f = fb::encode_heartbeat(2, 0x33, 0);  // no such NMT state
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::board, m), fb::DecodeResult::malformed);
  f = fb::encode_demand(3, {});
  f.data[0] = 0x00;
  f.data[1] = 0x80;  // "invalid" is not a demand
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::nodes, m), fb::DecodeResult::malformed);
  f = fb::encode_drive(3, 0, true, 0);
  f.data[0] = 0x02;
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::nodes, m), fb::DecodeResult::malformed);
  // Other nodes' traffic and error frames are foreign, not malformed.
  EXPECT_EQ(fb::decode(fb::encode_position(9, {}, 0), k_ids, fb::Side::board, m), fb::DecodeResult::foreign);
  f = fb::encode_position(2, {}, 0);
  f.error = true;
  EXPECT_EQ(fb::decode(f, k_ids, fb::Side::board, m), fb::DecodeResult::foreign);
  // The board does not consume its own commands.
  EXPECT_EQ(fb::decode(fb::encode_demand(3, {}), k_ids, fb::Side::board, m), fb::DecodeResult::foreign);
}

// Random frames on our identifiers: every one is either accepted or refused; accepted ones
// re-encode to an equal payload where the encoding is canonical; nothing crashes.
TEST(FieldBusCodec, FuzzedFramesAreClassified) {
  std::mt19937 rng(7);
  const uint32_t functions[] = {fb::k_position, fb::k_current, fb::k_amp_status, fb::k_sample_fd, fb::k_heartbeat,
                                fb::k_demand, fb::k_drive, fb::k_demand_fd};
  const uint8_t lens[] = {0, 1, 2, 7, 8, 12, 24, 48, 64};
  int ok = 0, malformed = 0, foreign = 0;
  for (int i = 0; i < 200000; ++i) {
    CanFrame f;
    f.id = functions[rng() % 8] + 1 + rng() % 4;
    f.fd = rng() % 2;
    f.len = lens[rng() % 9];
    if (!f.fd && f.len > 8) f.len = 8;
    for (auto& b : f.data) b = static_cast<uint8_t>(rng());
    fb::Message m;
    for (auto side : {fb::Side::board, fb::Side::nodes}) {
      switch (fb::decode(f, k_ids, side, m)) {
        case fb::DecodeResult::ok: ++ok; break;
        case fb::DecodeResult::malformed: ++malformed; break;
        case fb::DecodeResult::foreign: ++foreign; break;
      }
    }
  }
  EXPECT_GT(ok, 1000);
  EXPECT_GT(malformed, 10000);
  EXPECT_GT(foreign, 10000);
}

amb::board::BoardConfig test_board() {
  auto b = amb::board::load_board("bath-amb-rig");
  b.comms.can.node_timeout_ms = 5;
  return b;
}

/// A controllable clock for the front end.
class ManualClock final : public amb::hal::Clock {
 public:
  int64_t t = 0;
  int64_t now_ns() override { return t; }
  int64_t wait_until_ns(int64_t d) override { t = d; return t; }
};

/// The board side of the field bus (FieldBusFrontEnd) on a loopback bus whose other end,
/// `nodes`, stands for the sensor and amplifier nodes; the clock is stepped by hand.
struct FrontEndRig {
  amb::board::BoardConfig board = test_board();
  amb::hal::sim::LoopbackCanBus boardside, nodes;
  ManualClock clock;
  std::optional<amb::fieldbus::FieldBusFrontEnd> fe;
  explicit FrontEndRig(amb::fw::Supervisor* sup = nullptr) {
    amb::hal::sim::LoopbackCanBus::connect(boardside, nodes);
    fe.emplace(boardside, clock, board.comms.can, sup);
  }
};

TEST(FieldBusFrontEnd, SamplesFlowAndMalformedFramesAreCountedNotUsed) {
  FrontEndRig r;
  amb::hal::AnalogInputs in;
  EXPECT_FALSE(r.fe->read(in));  // nothing yet
  r.nodes.send(fb::encode_position(2, {1e-6, 2e-6, 3e-6, 4e-6}, 0));
  CanFrame bad = fb::encode_position(2, {9e-6, 9e-6, 9e-6, 9e-6}, 0);
  bad.len = 6;
  r.nodes.send(bad);
  r.nodes.send(fb::encode_current(3, {0.1, 0.2, 0.3, 0.4}, 0));
  ASSERT_TRUE(r.fe->read(in));
  EXPECT_NEAR(in.displacement_m[3], 4e-6, 1e-7);
  EXPECT_NEAR(in.coil_current_a[2], 0.3, 1e-3);
  EXPECT_EQ(r.fe->counters().malformed, 1u);
  amb::hal::AnalogOutputs out;
  out.amplifiers_enabled = true;
  out.current_demand_a = {0.5, -0.5, 0.25, 0};
  r.fe->write(out);
  CanFrame f;
  fb::Message m;
  int demands = 0, drives = 0, heartbeats = 0;
  while (r.nodes.receive(f)) {
    ASSERT_EQ(fb::decode(f, k_ids, fb::Side::nodes, m), fb::DecodeResult::ok);
    demands += m.kind == fb::Kind::demand;
    drives += m.kind == fb::Kind::drive;
    heartbeats += m.kind == fb::Kind::heartbeat;
  }
  EXPECT_EQ(demands, 1);
  EXPECT_EQ(drives, 1);
  EXPECT_EQ(heartbeats, 1);
}

TEST(FieldBusFrontEnd, SilentNodeWhileLevitatedEntersSafeState) {
  amb::fw::Supervisor sup;
  sup.configure(test_board());
  FrontEndRig r(&sup);
  amb::hal::AnalogInputs in;
  amb::hal::AnalogOutputs out;
  amb::hal::DiscreteOutputs dout;
  auto period = [&] {
    r.nodes.send(fb::encode_position(2, {}, 0));
    r.nodes.send(fb::encode_current(3, {}, 0));
    r.clock.t += 100'000;
    const bool ok = r.fe->read(in);
    sup.step(in, ok, {}, out, dout);
    r.fe->write(out);
    CanFrame f;
    while (r.nodes.receive(f)) {
    }
  };
  period();
  ASSERT_TRUE(sup.post(amb::fw::Command::levitate));
  for (int i = 0; i < 10; ++i) period();
  ASSERT_EQ(sup.state(), amb::fw::State::levitating);
  // The amplifier node goes silent (the sensor node keeps sampling): after node_timeout_ms
  // (5 ms) the loop must be in the safe state.
  for (int i = 0; i < 70 && sup.state() != amb::fw::State::fault; ++i) {
    r.nodes.send(fb::encode_position(2, {}, 0));
    r.clock.t += 100'000;
    const bool ok = r.fe->read(in);
    sup.step(in, ok, {}, out, dout);
    r.fe->write(out);
  }
  EXPECT_EQ(sup.state(), amb::fw::State::fault);
  EXPECT_EQ(sup.status().fault, amb::fw::FaultReason::comm_timeout);
  EXPECT_FALSE(out.amplifiers_enabled);
  EXPECT_EQ(r.fe->counters().node_timeouts, 1u);
}

TEST(FieldBusFrontEnd, ReadAndWriteDoNotAllocate) {
  FrontEndRig r;
  amb::hal::AnalogInputs in;
  amb::hal::AnalogOutputs out;
  CanFrame bad = fb::encode_position(2, {}, 0);
  bad.len = 3;
  const long before = amb::test::allocations();
  for (int i = 0; i < 1000; ++i) {
    r.nodes.send(fb::encode_position(2, {}, 0));
    r.nodes.send(bad);
    r.clock.t += 100'000;
    r.fe->read(in);
    r.fe->write(out);
    CanFrame f;
    while (r.nodes.receive(f)) {
    }
  }
  EXPECT_EQ(amb::test::allocations() - before, 0);
  EXPECT_EQ(r.fe->counters().malformed, 1000u);
}

}  // namespace

// The analysis thread's board-status frame: speed, confidence, flags survive the codec; a
// lost speed is INT32_MIN on the wire and NaN after decoding, never a number.
TEST(FieldBusCodec, BoardStatusFrameRoundTripsAndALostSpeedStaysLost) {
  using namespace amb::fieldbus;
  BoardStatus s;
  s.speed_hz = 45.0;
  s.confidence = 0.98;
  s.flags = static_cast<uint8_t>(1u << 3);  // source tracker
  s.sequence = 5;
  s.tracker_mode = 2;
  const amb::hal::CanFrame f = encode_board_status(1, s);
  EXPECT_EQ(f.id, 0x501u);
  EXPECT_EQ(f.len, 8);
  const uint8_t expect[8] = {0xC8, 0xAF, 0x00, 0x00, 0x62, 0x08, 0x05, 0x02};  // docs/fieldbus.md example
  for (int i = 0; i < 8; ++i) EXPECT_EQ(f.data[static_cast<size_t>(i)], expect[i]) << i;
  BoardStatus d;
  ASSERT_TRUE(decode_board_status(f, 1, d));
  EXPECT_DOUBLE_EQ(d.speed_hz, 45.0);
  EXPECT_DOUBLE_EQ(d.confidence, 0.98);
  EXPECT_EQ(d.flags, s.flags);
  s.speed_hz = std::nan("");
  s.flags |= status_speed_lost;
  const amb::hal::CanFrame g = encode_board_status(1, s);
  EXPECT_EQ(g.data[3], 0x80);
  ASSERT_TRUE(decode_board_status(g, 1, d));
  EXPECT_TRUE(std::isnan(d.speed_hz));
  EXPECT_FALSE(decode_board_status(g, 2, d)) << "another board's id";
  amb::hal::CanFrame bad = f;
  bad.data[4] = 101;
  EXPECT_FALSE(decode_board_status(bad, 1, d)) << "confidence above 100 %";
  bad = f;
  bad.len = 7;
  EXPECT_FALSE(decode_board_status(bad, 1, d));
}
