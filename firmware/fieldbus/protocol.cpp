#include "firmware/fieldbus/protocol.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>

namespace amb::fieldbus {

namespace {

int16_t to_i16(double v, double lsb) {
  if (std::isnan(v)) return k_invalid_i16;
  const double q = std::round(v / lsb);
  if (q >= 32767.0) return 32767;
  if (q <= -32767.0) return -32767;  // -32768 is reserved for "invalid"
  return static_cast<int16_t>(q);
}

int32_t to_i32(double v, double lsb) {
  if (std::isnan(v)) return k_invalid_i32;
  const double q = std::round(v / lsb);
  if (q >= 2147483647.0) return 2147483647;
  if (q <= -2147483647.0) return -2147483647;
  return static_cast<int32_t>(q);
}

// Little-endian field access on the frame payload.
void put16(hal::CanFrame& f, int at, uint16_t v) {
  f.data[static_cast<size_t>(at)] = static_cast<uint8_t>(v);
  f.data[static_cast<size_t>(at + 1)] = static_cast<uint8_t>(v >> 8);
}
void put32(hal::CanFrame& f, int at, uint32_t v) {
  for (int i = 0; i < 4; ++i) f.data[static_cast<size_t>(at + i)] = static_cast<uint8_t>(v >> (8 * i));
}
uint16_t get16(const hal::CanFrame& f, int at) {
  return static_cast<uint16_t>(f.data[static_cast<size_t>(at)] | (f.data[static_cast<size_t>(at + 1)] << 8));
}
uint32_t get32(const hal::CanFrame& f, int at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(f.data[static_cast<size_t>(at + i)]) << (8 * i);
  return v;
}

hal::CanFrame frame(uint32_t id, uint8_t len, bool fd) {
  hal::CanFrame f;
  f.id = id;
  f.len = len;
  f.fd = fd;
  return f;
}

// Four int16 channels into `f`: value / lsb, or invalid where the channel's bit of
// `fault_bits` is set (get_channels16 reads them back).
hal::CanFrame put_channels16(hal::CanFrame f, const std::array<double, 4>& v, double lsb, uint32_t fault_bits) {
  for (int i = 0; i < 4; ++i)
    put16(f, 2 * i, static_cast<uint16_t>((fault_bits >> i) & 1u ? k_invalid_i16 : to_i16(v[static_cast<size_t>(i)], lsb)));
  return f;
}

// Four int16 channels: value * lsb, or invalid (NaN + fault bit).
void get_channels16(const hal::CanFrame& f, double lsb, std::array<double, 4>& v, uint32_t& faults) {
  for (int i = 0; i < 4; ++i) {
    const auto raw = static_cast<int16_t>(get16(f, 2 * i));
    if (raw == k_invalid_i16) {
      v[static_cast<size_t>(i)] = std::numeric_limits<double>::quiet_NaN();
      faults |= 1u << i;
    } else {
      v[static_cast<size_t>(i)] = raw * lsb;
    }
  }
}
void get_channels32(const hal::CanFrame& f, int at, double lsb, std::array<double, 4>& v, uint32_t& faults, int bit0) {
  for (int i = 0; i < 4; ++i) {
    const auto raw = static_cast<int32_t>(get32(f, at + 4 * i));
    if (raw == k_invalid_i32) {
      v[static_cast<size_t>(i)] = std::numeric_limits<double>::quiet_NaN();
      faults |= 1u << (bit0 + i);
    } else {
      v[static_cast<size_t>(i)] = raw * lsb;
    }
  }
}

}  // namespace

hal::CanFrame encode_position(uint8_t node, const std::array<double, 4>& d, uint32_t fault_bits) {
  return put_channels16(frame(k_position + node, 8, false), d, k_position_lsb_m, fault_bits);
}

hal::CanFrame encode_current(uint8_t node, const std::array<double, 4>& c, uint32_t fault_bits) {
  return put_channels16(frame(k_current + node, 8, false), c, k_current_lsb_a, fault_bits);
}

hal::CanFrame encode_demand(uint8_t node, const std::array<double, 4>& c) {
  hal::CanFrame f = frame(k_demand + node, 8, false);
  for (int i = 0; i < 4; ++i) put16(f, 2 * i, static_cast<uint16_t>(to_i16(c[static_cast<size_t>(i)], k_current_lsb_a)));
  return f;
}

hal::CanFrame encode_drive(uint8_t node, uint16_t seq, bool enabled, double speed_hz) {
  hal::CanFrame f = frame(k_drive + node, 8, false);
  f.data[0] = enabled ? drive_amplifiers_enabled : 0;
  f.data[1] = static_cast<uint8_t>(seq);
  put16(f, 2, 0);
  put32(f, 4, static_cast<uint32_t>(to_i32(speed_hz, k_speed_lsb_hz)));
  return f;
}

hal::CanFrame encode_amp_status(uint8_t node, uint16_t seq, uint8_t flags, double dc_bus_v, double temperature_c,
                                uint16_t fault_code) {
  hal::CanFrame f = frame(k_amp_status + node, 8, false);
  f.data[0] = flags & 0x0F;
  f.data[1] = static_cast<uint8_t>(seq);
  put16(f, 2, static_cast<uint16_t>(std::clamp(std::lround(dc_bus_v * 10.0), 0L, 65535L)));
  put16(f, 4, static_cast<uint16_t>(to_i16(temperature_c, 0.1)));
  put16(f, 6, fault_code);
  return f;
}

hal::CanFrame encode_sample_fd(uint8_t node, uint16_t seq, const std::array<double, 4>& d,
                               const std::array<double, 4>& c, double tach_hz, uint32_t fault_bits) {
  hal::CanFrame f = frame(k_sample_fd + node, 48, true);
  put16(f, 0, seq);
  f.data[2] = static_cast<uint8_t>(fault_bits);
  f.data[3] = 0;
  for (int i = 0; i < 4; ++i) {
    put32(f, 4 + 4 * i,
          static_cast<uint32_t>((fault_bits >> i) & 1u ? k_invalid_i32 : to_i32(d[static_cast<size_t>(i)], k_position_fd_lsb_m)));
    put32(f, 20 + 4 * i,
          static_cast<uint32_t>((fault_bits >> (4 + i)) & 1u ? k_invalid_i32
                                                               : to_i32(c[static_cast<size_t>(i)], k_current_fd_lsb_a)));
  }
  put32(f, 36, static_cast<uint32_t>(tach_hz < 0 ? -1 : to_i32(tach_hz, k_speed_lsb_hz)));
  return f;
}

hal::CanFrame encode_demand_fd(uint8_t node, uint16_t seq, bool enabled, double speed_hz,
                               const std::array<double, 4>& c) {
  hal::CanFrame f = frame(k_demand_fd + node, 24, true);
  put16(f, 0, seq);
  f.data[2] = enabled ? drive_amplifiers_enabled : 0;
  f.data[3] = 0;
  put32(f, 4, static_cast<uint32_t>(to_i32(speed_hz, k_speed_lsb_hz)));
  for (int i = 0; i < 4; ++i) put32(f, 8 + 4 * i, static_cast<uint32_t>(to_i32(c[static_cast<size_t>(i)], k_current_fd_lsb_a)));
  return f;
}

hal::CanFrame encode_heartbeat(uint8_t node, uint8_t nmt_state, uint8_t node_state) {
  hal::CanFrame f = frame(k_heartbeat + node, 2, false);
  f.data[0] = nmt_state;
  f.data[1] = node_state;
  return f;
}

hal::CanFrame encode_board_status(uint8_t board_node, const BoardStatus& s) {
  hal::CanFrame f = frame(k_board_status + board_node, 8, false);
  put32(f, 0, static_cast<uint32_t>(to_i32(s.speed_hz, k_speed_lsb_hz)));
  const double c = std::isfinite(s.confidence) ? std::clamp(s.confidence, 0.0, 1.0) : 0.0;
  f.data[4] = static_cast<uint8_t>(std::lround(c * 100.0));
  f.data[5] = static_cast<uint8_t>(s.flags & 0x7Fu);
  f.data[6] = s.sequence;
  f.data[7] = s.tracker_mode;
  return f;
}

bool decode_board_status(const hal::CanFrame& f, uint8_t board_node, BoardStatus& out) {
  if (f.error || f.extended || f.fd || f.id != static_cast<uint32_t>(k_board_status + board_node) || f.len != 8) return false;
  if (f.data[4] > 100 || (f.data[5] & 0x80u) != 0 || ((f.data[5] >> 3) & 3u) == 3u) return false;
  const auto mhz = static_cast<int32_t>(get32(f, 0));
  out.speed_hz = mhz == k_invalid_i32 ? std::numeric_limits<double>::quiet_NaN() : mhz * k_speed_lsb_hz;
  out.confidence = f.data[4] / 100.0;
  out.flags = f.data[5];
  out.sequence = f.data[6];
  out.tracker_mode = f.data[7];
  return true;
}

hal::CanFrame encode_sweep_status(uint8_t board_node, const SweepStatusFrame& s) {
  hal::CanFrame f = frame(k_sweep_status + board_node, 8, false);
  const unsigned axis = s.axis < 0 || s.axis > 3 ? 0u : static_cast<unsigned>(s.axis) + 1u;
  f.data[0] = static_cast<uint8_t>((s.state & 0x0Fu) | axis << 4);
  f.data[1] = s.axes_done;
  f.data[2] = s.axes_total;
  put16(f, 3, s.period);
  f.data[5] = s.aborts;
  f.data[6] = s.refusals;
  f.data[7] = static_cast<uint8_t>((s.last_abort & 0x0Fu) | (s.last_refusal & 0x0Fu) << 4);
  return f;
}

bool decode_sweep_status(const hal::CanFrame& f, uint8_t board_node, SweepStatusFrame& out) {
  if (f.error || f.extended || f.fd || f.id != static_cast<uint32_t>(k_sweep_status + board_node) || f.len != 8) return false;
  const unsigned state = f.data[0] & 0x0Fu, axis = f.data[0] >> 4;
  if (state > 3 || axis > 4 || f.data[1] > 4 || f.data[2] > 4 || f.data[1] > f.data[2]) return false;
  out.state = static_cast<uint8_t>(state);
  out.axis = static_cast<int8_t>(static_cast<int>(axis) - 1);
  out.axes_done = f.data[1];
  out.axes_total = f.data[2];
  out.period = get16(f, 3);
  out.aborts = f.data[5];
  out.refusals = f.data[6];
  out.last_abort = f.data[7] & 0x0Fu;
  out.last_refusal = static_cast<uint8_t>(f.data[7] >> 4);
  return true;
}

DecodeResult decode(const hal::CanFrame& f, const NodeIds& ids, Side side, Message& m) {
  if (f.error || f.extended) return DecodeResult::foreign;
  const uint8_t node = static_cast<uint8_t>(f.id & k_node_mask);
  const uint32_t function = f.id & ~k_node_mask;
  m = Message{};
  m.node = node;
  auto want = [&](uint8_t len, bool fd) { return f.len == len && f.fd == fd; };

  if (function == k_heartbeat) {
    const bool ours = side == Side::board ? (node == ids.sensor || node == ids.amplifier) : node == ids.board;
    if (!ours) return DecodeResult::foreign;
    if (f.len < 1 || f.len > 2 || f.fd) return DecodeResult::malformed;
    const uint8_t s = f.data[0] & 0x7F;
    if (s != nmt_boot && s != nmt_stopped && s != nmt_operational && s != nmt_preoperational)
      return DecodeResult::malformed;
    m.kind = Kind::heartbeat;
    m.nmt_state = s;
    m.node_state = f.len > 1 ? f.data[1] : 0;
    return DecodeResult::ok;
  }

  if (side == Side::board) {
    if (function == k_position && node == ids.sensor) {
      if (!want(8, false)) return DecodeResult::malformed;
      m.kind = Kind::position;
      get_channels16(f, k_position_lsb_m, m.displacement_m, m.fault_bits);
      return DecodeResult::ok;
    }
    if (function == k_current && node == ids.amplifier) {
      if (!want(8, false)) return DecodeResult::malformed;
      m.kind = Kind::current;
      get_channels16(f, k_current_lsb_a, m.current_a, m.fault_bits);
      return DecodeResult::ok;
    }
    if (function == k_amp_status && node == ids.amplifier) {
      if (!want(8, false) || (f.data[0] & 0xF0) != 0) return DecodeResult::malformed;
      m.kind = Kind::amp_status;
      m.flags = f.data[0];
      m.sequence = f.data[1];
      m.dc_bus_v = get16(f, 2) * 0.1;
      m.temperature_c = static_cast<int16_t>(get16(f, 4)) * 0.1;
      m.amp_fault_code = get16(f, 6);
      return DecodeResult::ok;
    }
    if (function == k_sample_fd && node == ids.sensor) {
      if (!want(48, true) || f.data[3] != 0) return DecodeResult::malformed;
      m.kind = Kind::sample_fd;
      m.sequence = get16(f, 0);
      get_channels32(f, 4, k_position_fd_lsb_m, m.displacement_m, m.fault_bits, 0);
      get_channels32(f, 20, k_current_fd_lsb_a, m.current_a, m.fault_bits, 4);
      const auto tach = static_cast<int32_t>(get32(f, 36));
      m.speed_hz = tach < 0 ? -1.0 : tach * k_speed_lsb_hz;
      return DecodeResult::ok;
    }
    return DecodeResult::foreign;
  }

  // Nodes' side: commands addressed to the amplifier node.
  if (node != ids.amplifier) return DecodeResult::foreign;
  if (function == k_demand) {
    if (!want(8, false)) return DecodeResult::malformed;
    m.kind = Kind::demand;
    uint32_t faults = 0;
    get_channels16(f, k_current_lsb_a, m.current_a, faults);
    if (faults) return DecodeResult::malformed;  // a demand is never "invalid"
    return DecodeResult::ok;
  }
  if (function == k_drive) {
    if (!want(8, false) || (f.data[0] & ~drive_amplifiers_enabled) != 0 || get16(f, 2) != 0)
      return DecodeResult::malformed;
    m.kind = Kind::drive;
    m.flags = f.data[0];
    m.sequence = f.data[1];
    m.speed_hz = static_cast<int32_t>(get32(f, 4)) * k_speed_lsb_hz;
    return DecodeResult::ok;
  }
  if (function == k_demand_fd) {
    if (!want(24, true) || (f.data[2] & ~drive_amplifiers_enabled) != 0 || f.data[3] != 0)
      return DecodeResult::malformed;
    m.kind = Kind::demand_fd;
    m.sequence = get16(f, 0);
    m.flags = f.data[2];
    m.speed_hz = static_cast<int32_t>(get32(f, 4)) * k_speed_lsb_hz;
    uint32_t faults = 0;
    get_channels32(f, 8, k_current_fd_lsb_a, m.current_a, faults, 0);
    if (faults) return DecodeResult::malformed;
    return DecodeResult::ok;
  }
  return DecodeResult::foreign;
}

}  // namespace amb::fieldbus
