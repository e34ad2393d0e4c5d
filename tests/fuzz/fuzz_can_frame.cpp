// CAN frames come from other nodes on a shared field bus. The input is cut into frames
// (1 flag byte, 4 identifier bytes, 1 length byte, payload); each is decoded from both sides
// (board and bench nodes), and the whole sequence is fed through the board's field-bus front
// end as a real bus would deliver it. Decoding must classify every frame (ok, foreign,
// malformed) without reading past its payload; the front end must count, not crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "firmware/comms/comms_params.hpp"
#include "firmware/fieldbus/field_bus_front_end.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "hal/interfaces.hpp"

namespace {

class FuzzBus final : public amb::hal::CanBus {
 public:
  std::vector<amb::hal::CanFrame> rx;
  size_t next = 0;
  bool send(const amb::hal::CanFrame&) override { return true; }
  bool receive(amb::hal::CanFrame& f) override {
    if (next >= rx.size()) return false;
    f = rx[next++];
    return true;
  }
  amb::hal::CanStats stats() const override { return {}; }
};

class StepClock final : public amb::hal::Clock {
 public:
  int64_t t_ns = 0;
  int64_t now_ns() override { return t_ns += 100'000; }
  int64_t wait_until_ns(int64_t deadline_ns) override { return t_ns = deadline_ns; }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzBus bus;
  size_t i = 0;
  while (i + 6 <= size && bus.rx.size() < 256) {
    amb::hal::CanFrame f;
    const uint8_t flags = data[i];
    f.extended = flags & 1u;
    f.fd = flags & 2u;
    f.error = flags & 4u;
    uint32_t id = 0;
    std::memcpy(&id, data + i + 1, 4);
    f.id = f.extended ? (id & 0x1FFFFFFFu) : (id & 0x7FFu);
    f.len = static_cast<uint8_t>(data[i + 5] % 65);
    i += 6;
    const size_t n = std::min<size_t>(f.len, size - i);
    std::memcpy(f.data.data(), data + i, n);
    i += n;
    bus.rx.push_back(f);
  }
  const amb::fieldbus::NodeIds ids{};
  for (const auto& f : bus.rx) {
    for (auto side : {amb::fieldbus::Side::board, amb::fieldbus::Side::nodes}) {
      amb::fieldbus::Message m;
      const auto r = amb::fieldbus::decode(f, ids, side, m);
      if (r == amb::fieldbus::DecodeResult::ok) {
        // An invalid channel decodes as NaN with its fault bit set; never an infinity, and
        // never a NaN the fault bits do not announce (it would reach the control law).
        for (double v : m.displacement_m)
          if (std::isinf(v) || (std::isnan(v) && m.fault_bits == 0)) __builtin_trap();
        for (double v : m.current_a)
          if (std::isinf(v) || (std::isnan(v) && m.fault_bits == 0)) __builtin_trap();
      }
    }
  }
  for (bool fd : {false, true}) {
    bus.next = 0;
    StepClock clock;
    amb::comms::CanParams params;
    params.fd = fd;
    amb::fieldbus::FieldBusFrontEnd fe(bus, clock, params, nullptr);
    amb::hal::AnalogInputs in{};
    for (int k = 0; k < 8; ++k) fe.read(in);
    (void)fe.counters();
  }
  return 0;
}
