#include "tests/sil/fault_rig.hpp"

#include <arpa/inet.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <pthread.h>
#include <sched.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "firmware/analysis/analysis_thread.hpp"
#include "firmware/app/loop_runner.hpp"
#include "firmware/app/sample_fanout.hpp"
#include "firmware/board/board.hpp"
#include "firmware/capture/floating_capture.hpp"
#include "firmware/common/spsc_ring.hpp"
#include "firmware/events/event_codec.hpp"
#include "firmware/events/event_writer.hpp"
#include "firmware/fieldbus/field_bus_front_end.hpp"
#include "firmware/fieldbus/protocol.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_map.hpp"
#include "hal/linux/file_storage.hpp"
#include "hal/linux/linux_clock.hpp"
#include "hal/linux/modbus_tcp_server.hpp"
#include "host-tools/core/link/board_link.hpp"

namespace amb::sil::faults {

namespace {

namespace fb = fieldbus;
namespace lx = hal::linux_hw;
namespace lk = host::link;
namespace regs = fw::regs;
using Clock = std::chrono::steady_clock;

constexpr uint32_t k_arm_key = 0x19C0FFEE;

bool is_storage_fault(Fault f) {
  return f == Fault::storage_full || f == Fault::storage_full_other || f == Fault::storage_eio ||
         f == Fault::storage_read_only || f == Fault::storage_slow_fsync;
}

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
void sleep_s(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

// ---- the sensor and amplifier nodes on an in-process field bus ------------------------------------

/// The board's side of a field bus whose sensor and amplifier nodes are emulated in step with
/// the board: each demand frame the board sends is the period tick the nodes answer, in the
/// same order a real bus delivers (error and malformed frames injected first, then the position
/// and current frames; heartbeats every heartbeat period). The rotor is held at the bearing
/// centre with 0.2 um of noise; the amplifiers follow the demands. Frames go through a bounded
/// receive queue (1024, as a socket buffer): overflow drops and counts (rx_dropped).
/// send/receive: the loop thread; the fault switches and stats(): any thread.
class SimNodesBus final : public hal::CanBus {
 public:
  SimNodesBus(const comms::CanParams& p, hal::Clock& clock)
      : ids_{p.board_node_id, p.sensor_node_id, p.amplifier_node_id}, clock_(clock),
        heartbeat_ns_(static_cast<int64_t>(p.heartbeat_period_ms) * 1'000'000) {}

  std::atomic<int> error_frames_per_period{0};
  std::atomic<int> malformed_per_period{0};
  std::atomic<bool> sensor_silent{false};
  std::atomic<int> sensor_every{1};  ///< the sensor node samples every n-th period only (stale in between)

  bool send(const hal::CanFrame& f) override {
    bump(tx_);
    fb::Message m;
    if (fb::decode(f, ids_, fb::Side::nodes, m) != fb::DecodeResult::ok || m.kind != fb::Kind::demand) return true;
    // The period tick: the nodes answer.
    for (int i = error_frames_per_period.load(std::memory_order_relaxed); i > 0; --i) {
      hal::CanFrame e;
      e.id = 0x20000004;  // CAN_ERR_CRTL-style controller error
      e.error = true;
      e.len = 8;
      push(e);
    }
    for (int i = malformed_per_period.load(std::memory_order_relaxed); i > 0; --i) {
      hal::CanFrame bad = fb::encode_position(ids_.sensor, {}, 0);
      bad.len = 5;
      push(bad);
    }
    const bool silent = sensor_silent.load(std::memory_order_relaxed);
    const int every = std::max(1, sensor_every.load(std::memory_order_relaxed));
    if (!silent && ++tick_ % static_cast<uint64_t>(every) == 0) {
      std::array<double, 4> d{};
      for (double& x : d) x = noise() * 0.2e-6;
      push(fb::encode_position(ids_.sensor, d, 0));
    }
    push(fb::encode_current(ids_.amplifier, m.current_a, 0));
    const int64_t now = clock_.now_ns();
    if (now >= next_heartbeat_ns_) {
      next_heartbeat_ns_ = now + heartbeat_ns_;
      if (!silent) push(fb::encode_heartbeat(ids_.sensor, fb::nmt_operational, 0));
      push(fb::encode_heartbeat(ids_.amplifier, fb::nmt_operational, 0));
    }
    return true;
  }
  bool receive(hal::CanFrame& f) override {
    if (tail_ == head_) return false;
    f = q_[tail_++ & (k_cap - 1)];
    bump(rx_);
    if (f.error) bump(err_);
    return true;
  }
  hal::CanStats stats() const override {
    hal::CanStats s;
    s.tx_frames = tx_.load(std::memory_order_relaxed);
    s.rx_frames = rx_.load(std::memory_order_relaxed);
    s.rx_dropped = rx_dropped_.load(std::memory_order_relaxed);
    s.error_frames = err_.load(std::memory_order_relaxed);
    return s;
  }

 private:
  static constexpr uint64_t k_cap = 1024;
  static void bump(std::atomic<uint64_t>& c) { c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed); }
  void push(const hal::CanFrame& f) {
    if (head_ - tail_ >= k_cap) {
      bump(rx_dropped_);
      return;
    }
    q_[head_++ & (k_cap - 1)] = f;
  }
  double noise() {  // uniform in [-1, 1), deterministic
    lcg_ = lcg_ * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(lcg_ >> 11) * 0x1.0p-52 - 1.0;
  }
  fb::NodeIds ids_;
  hal::Clock& clock_;
  int64_t heartbeat_ns_;
  int64_t next_heartbeat_ns_ = 0;
  uint64_t lcg_ = 19;
  uint64_t tick_ = 0;
  std::array<hal::CanFrame, k_cap> q_{};
  uint64_t head_ = 0, tail_ = 0;
  std::atomic<uint64_t> tx_{0}, rx_{0}, rx_dropped_{0}, err_{0};
};

class NullDio final : public hal::DiscreteIo {
 public:
  hal::DiscreteInputs read() override { return {}; }
  void write(const hal::DiscreteOutputs&) override {}
};

// ---- storage faults: the FileStorage seam ----------------------------------------------------

/// One injector for the two storage directories (events/, wear/): they share a file system.
class StorageFaults final : public lx::FsFaultHook {
 public:
  explicit StorageFaults(std::vector<std::string> dirs) : dirs_(std::move(dirs)) {}
  void set(Fault f, int slow_ms) {
    std::lock_guard<std::mutex> lock(m_);
    fault_ = f;
    slow_ms_ = slow_ms;
    if (f == Fault::storage_full) quota_ = usage();  // full at its present use: dropping old events makes room
    // storage_full_other: a runaway writer elsewhere takes every byte that is freed (free stays 0).
  }
  void clear() { set(Fault::none, 0); }
  uint64_t injected() const { return injected_.load(); }

  int before(lx::FsOp op, std::string_view, uint64_t bytes) override {
    Fault f;
    int slow;
    {
      std::lock_guard<std::mutex> lock(m_);
      f = fault_;
      slow = slow_ms_;
    }
    switch (f) {
      case Fault::storage_eio:
        return op == lx::FsOp::fsync ? count(EIO) : 0;
      case Fault::storage_read_only:
        return op == lx::FsOp::create || op == lx::FsOp::rename || op == lx::FsOp::unlink ? count(EROFS) : 0;
      case Fault::storage_slow_fsync:
        if (op == lx::FsOp::fsync || op == lx::FsOp::fsync_dir) {
          std::this_thread::sleep_for(std::chrono::milliseconds(slow));
          injected_.fetch_add(1);
        }
        return 0;
      case Fault::storage_full: {
        if (op != lx::FsOp::write) return 0;
        std::lock_guard<std::mutex> lock(m_);
        return usage() + bytes > quota_ ? count(ENOSPC) : 0;
      }
      case Fault::storage_full_other:
        return op == lx::FsOp::write ? count(ENOSPC) : 0;
      default:
        return 0;
    }
  }
  int64_t free_bytes(std::string_view) override {
    std::lock_guard<std::mutex> lock(m_);
    if (fault_ == Fault::storage_full_other) return 0;
    if (fault_ != Fault::storage_full) return -1;
    const uint64_t u = usage();
    return u >= quota_ ? 0 : static_cast<int64_t>(quota_ - u);
  }

 private:
  int count(int e) {
    injected_.fetch_add(1);
    return e;
  }
  uint64_t usage() const {
    uint64_t u = 0;
    std::error_code ec;
    for (const auto& d : dirs_)
      for (const auto& e : std::filesystem::directory_iterator(d, ec))
        if (e.is_regular_file(ec)) u += e.file_size(ec);
    return u;
  }
  std::vector<std::string> dirs_;
  mutable std::mutex m_;
  Fault fault_ = Fault::none;
  int slow_ms_ = 0;
  uint64_t quota_ = 0;
  std::atomic<uint64_t> injected_{0};
};

// ---- the loop thread with per-window latency ------------------------------------------------

/// Latency histogram of one window, 1 us bins (last bin: overflow). Filled by the loop thread only.
struct WindowHist {
  static constexpr size_t k_bins = 20000;
  std::vector<uint32_t> bins = std::vector<uint32_t>(k_bins, 0);
  uint64_t periods = 0, overruns = 0;
  double sum_ns = 0, max_ns = 0;
  WindowStats stats() const {
    WindowStats w;
    w.periods = periods;
    w.overruns = overruns;
    w.mean_us = periods ? sum_ns / static_cast<double>(periods) * 1e-3 : 0.0;
    w.max_us = max_ns * 1e-3;
    auto q = [&](double f) {
      const double target = f * static_cast<double>(periods);
      double acc = 0;
      for (size_t i = 0; i < k_bins; ++i) {
        acc += bins[i];
        if (acc >= target && acc > 0) return i + 1 < k_bins ? static_cast<double>(i + 1) : w.max_us;
      }
      return w.max_us;
    };
    w.p50_us = q(0.5);
    w.p99_us = q(0.99);
    w.p999_us = q(0.999);
    return w;
  }
};

// ---- Modbus load -------------------------------------------------------------------------------

/// One raw TCP exchange (malformed frames): connect, send, wait briefly for an answer, close.
/// True when an answer came (only looked for with `linger`).
bool raw_exchange(uint16_t port, const std::vector<uint8_t>& bytes, bool linger, double hold_s = 0.0) {
  bool answered = false;
  const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (s < 0) return false;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval tv{0, 100'000};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
    (void)::send(s, bytes.data(), bytes.size(), MSG_NOSIGNAL);
    uint8_t reply[300];
    if (linger) answered = ::recv(s, reply, sizeof reply, 0) > 0;
    if (hold_s > 0) sleep_s(hold_s);  // a slow (or hostile) client sitting on a partial request
  }
  ::close(s);
  return answered;
}

struct FloodCounters {
  std::atomic<uint64_t> requests{0}, answered{0}, exceptions{0}, connect_failures{0}, malformed_sent{0};
  std::atomic<unsigned> malformed_kinds_answered{0};  ///< bit k: a malformed frame of kind k was answered
};

/// A client that connects, sends a burst of mixed requests (valid reads, unknown addresses,
/// writes to read-only registers, unarmed commands, arms with a wrong key, oversized reads),
/// disconnects, and again, until `stop` or the request bound.
void flood_client(uint16_t port, int id, const std::atomic<bool>& stop, FloodCounters& fc, uint64_t max_requests) {
  std::mt19937 rng(static_cast<uint32_t>(1000 + id));
  uint16_t r[125];
  while (!stop.load() && fc.requests.load() < max_requests) {
    modbus_t* c = modbus_new_tcp("127.0.0.1", port);
    modbus_set_response_timeout(c, 0, 300'000);
    modbus_set_slave(c, 1);
    if (modbus_connect(c) != 0) {
      fc.connect_failures.fetch_add(1);
      modbus_free(c);
      sleep_s(0.002);
      continue;
    }
    for (int i = 0; i < 40 && !stop.load(); ++i) {
      int rc = 0;
      switch (rng() % 9) {
        case 0: rc = modbus_read_registers(c, regs::state, 10, r); break;
        case 1: rc = modbus_read_registers(c, regs::loop_periods, 16, r); break;
        case 2: rc = modbus_read_registers(c, 0x7000, 4, r); break;                        // unknown address
        case 3: rc = modbus_write_register(c, regs::state, 1); break;                      // read-only
        case 4: rc = modbus_write_register(c, regs::command, regs::op_emergency_stop); break; // not armed
        case 5: {                                                                          // wrong key
          const uint16_t v[3] = {0x1234, 0x5678, regs::op_levitate};
          rc = modbus_write_registers(c, regs::arm, 3, v);
          break;
        }
        case 6: rc = modbus_read_registers(c, regs::dl_status, 122, r); break;
        case 7: rc = modbus_read_registers(c, regs::can_stats, 46, r); break;
        default: rc = modbus_read_registers(c, regs::identity, 24, r); break;
      }
      fc.requests.fetch_add(1);
      if (rc >= 0) fc.answered.fetch_add(1);
      else if (errno > MODBUS_ENOBASE && errno < MODBUS_ENOBASE + 20) fc.exceptions.fetch_add(1);
      else break;  // connection refused (max_clients) or closed: reconnect
    }
    modbus_close(c);
    modbus_free(c);
  }
}

/// Malformed frames on raw sockets: garbage, wrong protocol id, a length field that lies (short
/// and long), a truncated header, an unknown function, a wrong unit.
void malformed_client(uint16_t port, int id, const std::atomic<bool>& stop, FloodCounters& fc, uint64_t max_requests) {
  std::mt19937 rng(static_cast<uint32_t>(77 + id));
  // Every kind in turn (the one-second hold last), so each is sent within a client's first
  // seven frames even when a slow build (TSan) lets a client send only a few.
  // A frame the server should answer (wrong unit, unknown function) that got no answer was
  // refused for want of a free slot (the flood holds them) or not read yet: it is sent again,
  // up to four times, before the next kind.
  unsigned kind = 5 + static_cast<unsigned>(id);
  int unanswered = 0;
  while (!stop.load() && fc.requests.load() < max_requests) {
    std::vector<uint8_t> b;
    bool linger = true;
    double hold_s = 0.0;
    const unsigned this_kind = kind % 7;
    switch (this_kind) {
      case 0: b.resize(1 + rng() % 40); for (auto& x : b) x = static_cast<uint8_t>(rng()); break;
      case 1: b = {0, 1, 0x12, 0x34, 0, 6, 1, 3, 0, 0, 0, 1}; break;          // protocol id != 0
      case 2: b = {0, 2, 0, 0, 0, 3, 1, 3, 0, 0, 0, 1}; break;                // length says 3, 6 follow
      case 3: b = {0, 4, 0, 0}; linger = false; break;                        // truncated header
      case 4: b = {0, 5, 0, 0, 0, 2, 1, 0x2B}; break;                         // function not served
      case 5: b = {0, 6, 0, 0, 0, 6, 99, 3, 0, 0, 0, 1}; break;               // another unit
      default: b = {0, 3, 0, 0, 0, 40, 1, 3, 0, 0, 0, 1}; linger = false; hold_s = 1.2; break; // length 40: the rest never comes
    }
    const bool answered = raw_exchange(port, b, linger, hold_s);
    fc.malformed_sent.fetch_add(1);
    fc.requests.fetch_add(1);
    const bool expects_answer = this_kind == 4 || this_kind == 5;
    if (answered) fc.malformed_kinds_answered.fetch_or(1u << this_kind);
    if (expects_answer && !answered && ++unanswered < 5) continue;
    unanswered = 0;
    ++kind;
  }
}

// ---- counters over Modbus -----------------------------------------------------------------------

std::map<std::string, uint64_t> read_counters(lk::ModbusLink& link) {
  std::map<std::string, uint64_t> m;
  std::vector<uint16_t> r(125);
  auto u32 = [&](size_t at) { return static_cast<uint64_t>(lk::u32_at(r, at)); };
  link.read(regs::faults, std::span<uint16_t>(r.data(), 10));
  m["faults.read_failures"] = u32(0);
  m["faults.sensor_fault_samples"] = u32(2);
  m["faults.safe_state_entries"] = u32(8);
  link.read(regs::loop_periods, std::span<uint16_t>(r.data(), 16));
  m["loop.overruns"] = lk::u64_at(r, 4);
  link.read(regs::can_stats, std::span<uint16_t>(r.data(), regs::stats_end - regs::can_stats));
  const char* can[] = {"can.tx", "can.rx", "can.tx_dropped", "can.rx_dropped", "can.error_frames", "can.bus_off", "can.malformed"};
  for (size_t i = 0; i < 7; ++i) m[can[i]] = u32(2 * i);
  const char* fbn[] = {"fieldbus.samples", "fieldbus.stale_periods", "fieldbus.malformed", "fieldbus.node_timeouts",
                       "fieldbus.amp_faults", "fieldbus.tx_failures"};
  for (size_t i = 0; i < 6; ++i) m[fbn[i]] = u32(0x10 + 2 * i);
  const char* mb[] = {"modbus.requests", "modbus.exceptions", "modbus.bad_frames", "modbus.wrong_unit",
                      "modbus.connections", "modbus.refused_state", "modbus.illegal_address"};
  for (size_t i = 0; i < 7; ++i) m[mb[i]] = u32(0x20 + 2 * i);
  link.read(regs::access_stats, std::span<uint16_t>(r.data(), regs::access_end - regs::access_stats));
  const char* ac[] = {"modbus.arms", "modbus.arm_key_mismatch", "modbus.commands", "modbus.refused_not_armed",
                      "modbus.refused_state_detail", "modbus.refused_value", "modbus.refused_connections"};
  for (size_t i = 0; i < 7; ++i) m[ac[i]] = u32(2 * i);
  m.erase("modbus.refused_state_detail");
  link.read(regs::storage_stats, std::span<uint16_t>(r.data(), regs::storage_end - regs::storage_stats));
  const char* st[] = {"storage.written", "storage.refused",  "storage.dropped_oldest", "storage.write_errors",
                      "storage.no_space", "storage.retries",  "storage.pending",        "storage.lost",
                      "storage.wear_commit_failures"};
  for (size_t i = 0; i < 9; ++i) m[st[i]] = u32(2 * i);
  return m;
}

const char* fault_counter_of(Fault f) {
  switch (f) {
    case Fault::none: return "-";
    case Fault::modbus_flood: return "modbus.bad_frames, modbus.exceptions, modbus.refused_connections, modbus.refused_not_armed, modbus.arm_key_mismatch";
    case Fault::can_errors: return "can.error_frames, fieldbus.malformed";
    case Fault::can_babble: return "can.error_frames, can.rx_dropped, fieldbus.stale_periods, faults.read_failures -> fault sensor_invalid";
    case Fault::sensor_silent: return "faults.read_failures -> fault sensor_invalid (after 10 periods), fieldbus.node_timeouts (after node_timeout_ms)";
    case Fault::sensor_stale: return "fieldbus.stale_periods, faults.read_failures -> fault sensor_invalid";
    case Fault::storage_full: return "storage.dropped_oldest, storage.wear_commit_failures";
    case Fault::storage_full_other: return "storage.no_space, storage.retries, storage.pending, storage.wear_commit_failures";
    case Fault::storage_eio:
    case Fault::storage_read_only: return "storage.write_errors, storage.retries, storage.pending, storage.wear_commit_failures";
    case Fault::storage_slow_fsync: return "loop unaffected; storage.pending while slow";
  }
  return "?";
}

}  // namespace

const char* to_string(Fault f) {
  switch (f) {
    case Fault::none: return "none";
    case Fault::modbus_flood: return "modbus_flood";
    case Fault::can_errors: return "can_errors";
    case Fault::can_babble: return "can_babble";
    case Fault::sensor_silent: return "sensor_silent";
    case Fault::sensor_stale: return "sensor_stale";
    case Fault::storage_full: return "storage_full";
    case Fault::storage_full_other: return "storage_full_other";
    case Fault::storage_eio: return "storage_eio";
    case Fault::storage_read_only: return "storage_read_only";
    case Fault::storage_slow_fsync: return "storage_slow_fsync";
  }
  return "?";
}

std::vector<Fault> all_faults() {
  return {Fault::none,         Fault::modbus_flood,       Fault::can_errors,  Fault::can_babble,
          Fault::sensor_silent, Fault::sensor_stale,      Fault::storage_full, Fault::storage_full_other,
          Fault::storage_eio,  Fault::storage_read_only,  Fault::storage_slow_fsync};
}

bool parse_fault(const std::string& name, Fault& out) {
  for (Fault f : all_faults())
    if (name == to_string(f)) {
      out = f;
      return true;
    }
  return false;
}

std::string RigResult::json() const {
  auto w = [](const WindowStats& s) {
    return nlohmann::json{{"periods", s.periods}, {"overruns", s.overruns}, {"p50_us", s.p50_us},
                          {"p99_us", s.p99_us},   {"p999_us", s.p999_us},   {"max_us", s.max_us},
                          {"mean_us", s.mean_us}};
  };
  nlohmann::json j{{"fault", to_string(fault)},
                   {"sched_fifo", realtime},
                   {"levitated", levitated},
                   {"quiet", w(quiet)},
                   {"fault_window", w(faulted)},
                   {"recovery", w(recovery)},
                   {"events",
                    {{"captures_requested", captures_requested}, {"frozen", events_frozen}, {"written", written},
                     {"refused", refused}, {"dropped_oldest", dropped_oldest}, {"write_errors", write_errors},
                     {"retries", retries}, {"pending_at_end", pending_at_end}, {"capture_lost", capture_lost},
                     {"writer_lost", writer_lost}, {"lost", events_lost}, {"files_on_disk", files_on_disk}}},
                   {"torn", {{"events", events_torn}, {"wear_slots", wear_corrupt_slots}}},
                   {"wear_sequence", wear_sequence},
                   {"writebacks", writebacks},
                   {"state_after_fault", state_after_fault},
                   {"fault_reason_after_fault", fault_reason_after_fault},
                   {"relevitated", relevitated},
                   {"state_at_end", state_at_end},
                   {"fault_counter", fault_counter},
                   {"counters_fault_window", counters},
                   {"modbus_flood_requests", modbus_requests},
                   {"operator_command_max_ms", {{"quiet", command_max_ms_quiet}, {"fault", command_max_ms_fault}}},
                   {"operator_command_failures", command_failures},
                   {"wall_s", wall_s},
                   {"loadavg_at_start", loadavg}};
  return j.dump(2);
}

RigResult run_fault_rig(const RigOptions& o) {
  const auto t_start = Clock::now();
  RigResult res;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {  // how busy the machine was (shared hosts)
    char b[64] = {};
    if (std::fgets(b, sizeof b, f)) res.loadavg = std::strtod(b, nullptr);
    std::fclose(f);
  }
  res.fault = o.fault;
  res.fault_counter = fault_counter_of(o.fault);

  // ---- configure (as run_linux does) --------------------------------------------------------
  board::BoardConfig board = board::load_board("bath-amb-rig");
  board.comms.present = true;
  board.comms.modbus.arm_key = k_arm_key;
  board.comms.modbus.arm_window_ms = 5000;
  // Short windows so that many events go through the storage in a few seconds.
  board.capture.pre_trigger_s = 0.1;
  board.capture.post_trigger_s = 0.2;
  board.capture.rearm_hold_s = 0.05;
  board.capture.max_events = 64;  // the budget never binds here: dropped_oldest counts the storage_full fault only
  board.capture.event_buffers = 4;  // slack for a slow writer thread (sanitizer builds)

  const std::string dir = o.dir.empty() ? (std::filesystem::temp_directory_path() /
                                           ("amb-fault-rig-" + std::string(to_string(o.fault)) + "-" + std::to_string(::getpid())))
                                              .string()
                                        : o.dir;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  lx::FileStorage events_fs(dir + "/events"), wear_fs(dir + "/wear");
  StorageFaults storage_faults({dir + "/events", dir + "/wear"});
  events_fs.set_fault_hook(&storage_faults);
  wear_fs.set_fault_hook(&storage_faults);
  fw::WearStore wear(wear_fs, board.name);
  const fw::GenerationReport wear_report = wear.open();

  fw::Supervisor sup;
  sup.configure(board);
  lx::LinuxClock clock;
  SimNodesBus bus(board.comms.can, clock);
  fb::FieldBusFrontEnd fe(bus, clock, board.comms.can, &sup);
  NullDio dio;
  fw::FloatingCapture capture;
  fw::configure_capture(capture, board);
  fw::WriterOptions wo;
  wo.idle_sleep_ms = 2;
  wo.max_pending = o.max_pending;
  fw::EventWriter writer(capture, events_fs, board, wo);
  auto analysis = std::make_unique<fw::AnalysisTask>();
  if (std::string e = analysis->configure(board, &sup); !e.empty()) throw std::runtime_error("analysis task: " + e);
  fw::SampleFanout sinks;
  sinks.add(&capture);
  if (analysis->enabled()) sinks.add(analysis.get());
  fw::LoopRunner loop(clock, fe, dio, sup, &sinks);
  fw::SeqLock<fw::LoopStats> loop_stats;
  loop_stats.store(fw::LoopStats{});

  lx::ModbusTcpOptions mo;
  mo.bind_address = "127.0.0.1";
  mo.port = 0;
  mo.max_clients = board.comms.modbus.max_clients;
  lx::ModbusTcpServer server(mo);
  fw::RegisterSources src;
  src.supervisor = &sup;
  src.loop_stats = [&] { return loop_stats.load(); };
  src.can_stats = [&] { return bus.stats(); };
  src.fieldbus = [&] { return fe.counters(); };
  src.link = [&] {
    const auto s = server.stats();
    return fw::LinkCounters{s.requests, s.exceptions, s.bad_frames, s.wrong_unit, s.connections, s.refused_connections};
  };
  src.nodes_alive = [&] { return fe.nodes_alive(); };
  if (analysis->enabled()) src.analysis = [&] { return analysis->status(); };
  src.storage = [&] { return writer.store_counters(); };
  src.manual_capture = [&] { return capture.request_manual_trigger(); };
  src.now_ns = [] { return lx::monotonic_ns(); };
  src.arm_key = board.comms.modbus.arm_key;
  src.arm_window_ns = static_cast<int64_t>(board.comms.modbus.arm_window_ms) * 1'000'000;
  src.events = &events_fs;
  src.wear = &wear;
  src.wear_corrupt_at_start = wear_report.corrupt_slots;
  src.board_name = board.name;
  src.rate_hz = board.rate_hz;
  fw::RegisterMap map(src);
  std::string err;
  if (!server.start(map, err)) throw std::runtime_error(err);
  writer.start();
  fw::AnalysisThread analysis_thread;
  if (analysis->enabled()) analysis_thread.start(*analysis, board.tracker.poll_period_s);

  // ---- active: the loop thread ----------------------------------------------------------------
  std::array<WindowHist, 4> win;  // 0 lift-off, 1 quiet, 2 fault, 3 recovery
  std::atomic<int> window{0};
  std::atomic<bool> stop_loop{false};
  std::atomic<bool> fifo{false};
  std::thread loop_thread([&] {
    sched_param sp{};
    sp.sched_priority = 80;
    fifo = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &sp) == 0;
    const unsigned cpus = std::thread::hardware_concurrency();
    if (cpus > 1) {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(static_cast<int>(cpus - 1), &set);
      ::pthread_setaffinity_np(::pthread_self(), sizeof set, &set);
    }
    int64_t deadline = clock.now_ns() + loop.period_ns();
    double sum_prev = 0;
    uint64_t over_prev = 0, n = 0;
    while (!stop_loop.load(std::memory_order_relaxed)) {
      deadline = loop.run_one(deadline);
      const fw::LoopStats& s = loop.stats();
      WindowHist& h = win[static_cast<size_t>(window.load(std::memory_order_relaxed))];
      const double lat = s.sum_latency_ns - sum_prev;
      sum_prev = s.sum_latency_ns;
      ++h.periods;
      h.overruns += s.overruns - over_prev;
      over_prev = s.overruns;
      h.sum_ns += lat;
      h.max_ns = std::max(h.max_ns, lat);
      ++h.bins[std::min<size_t>(WindowHist::k_bins - 1, static_cast<size_t>(lat * 1e-3))];
      if ((++n & 15u) == 0) loop_stats.store(s);
    }
    loop_stats.store(loop.stats());
  });

  // Everything below is the operator, the SCADA poller and the fault; all over Modbus.
  lk::LinkOptions lo;
  lo.port = server.bound_port();
  lo.retry_delay_s = 0.05;
  lo.response_timeout_s = 3.0;
  std::unique_ptr<lk::ModbusLink> link;
  std::atomic<bool> stop_poll{false};
  std::thread poller;
  auto finish = [&] {
    stop_poll = true;
    if (poller.joinable()) poller.join();
    stop_loop = true;
    if (loop_thread.joinable()) loop_thread.join();
    analysis_thread.stop();
    writer.stop();
    server.stop();
  };
  try {
    link = std::make_unique<lk::ModbusLink>(lo);
    // A SCADA-like poller: the state and loop blocks at 10 Hz on its own connection.
    poller = std::thread([&] {
      lk::ModbusLink p(lo);
      std::vector<uint16_t> r(16);
      while (!stop_poll.load()) {
        try {
          p.read(regs::state, std::span<uint16_t>(r.data(), 10));
          p.read(regs::loop_periods, std::span<uint16_t>(r.data(), 16));
        } catch (const std::exception&) {
        }
        sleep_s(0.1);
      }
    });
    auto state_phase = [&] {
      std::vector<uint16_t> r(3);
      link->read(regs::state, r);
      return std::array<uint16_t, 3>{r[0], r[1], r[2]};
    };
    auto levitate = [&]() -> bool {
      lk::send_command(*link, k_arm_key, regs::op_levitate);
      const auto t0 = Clock::now();
      while (since(t0) < 10.0) {
        const auto s = state_phase();
        if (s[0] == static_cast<uint16_t>(fw::State::levitating) && s[1] == static_cast<uint16_t>(fw::Phase::levitated))
          return true;
        if (s[0] == static_cast<uint16_t>(fw::State::fault)) return false;
        sleep_s(0.05);
      }
      return false;
    };
    // Storage faults run with the rotor resting (the loop runs all the same, state inactive):
    // a wear-record commit is refused while the rotor is levitated, and the commit is the
    // storage's second user. The other faults run levitated (their write-backs are refused
    // with refused_unsafe: the answer still has to come through the load).
    res.levitated = !is_storage_fault(o.fault);
    if (res.levitated && !levitate())
      throw std::runtime_error("the rig did not levitate (state " + std::to_string(state_phase()[0]) + ")");

    // The load of every window: a manual capture every capture_period_s, one write-back.
    auto write_back_once = [&]() -> std::string {
      try {
        const lk::WearSummary w = lk::read_wear_summary(*link);
        fw::WearRecord rec;
        rec.sequence = w.present ? w.sequence + 1 : 1;
        rec.board_name = board.name;
        rec.life_model = "fault-rig";
        rec.event_count = rec.sequence;
        return lk::write_back(*link, fw::encode_wear_record(rec), k_arm_key).result_name;
      } catch (const std::exception& e) {
        return std::string("error: ") + e.what();
      }
    };
    auto run_window = [&](double seconds, bool do_writeback, const std::function<void()>& mid) {
      const auto t0 = Clock::now();
      double next_capture = 0.0;
      bool wb_done = !do_writeback, mid_done = !mid;
      while (since(t0) < seconds) {
        if (since(t0) >= next_capture) {
          try {
            const auto tc = Clock::now();
            lk::send_command(*link, k_arm_key, regs::k_command_capture);
            ++res.captures_requested;
            double& worst = window.load() == 2 ? res.command_max_ms_fault : res.command_max_ms_quiet;
            worst = std::max(worst, since(tc) * 1e3);
          } catch (const std::exception&) {
            ++res.command_failures;
          }
          next_capture += o.capture_period_s;
        }
        if (!wb_done && since(t0) > seconds / 2) {
          res.writebacks.push_back(write_back_once());
          wb_done = true;
        }
        if (!mid_done && since(t0) > seconds / 4) {
          mid();
          mid_done = true;
        }
        sleep_s(0.01);
      }
    };

    window = 1;
    run_window(o.window_s, true, {});
    const auto before = read_counters(*link);

    // ---- the fault window -------------------------------------------------------------------
    FloodCounters fc;
    std::atomic<bool> stop_flood{false};
    std::vector<std::thread> flood;
    window = 2;
    switch (o.fault) {
      case Fault::modbus_flood:
        // The malformed-frame clients first, so that they have connections before the flood
        // takes every free slot (max_clients).
        for (int i = 0; i < o.flood_malformed_clients; ++i)
          flood.emplace_back(malformed_client, server.bound_port(), i, std::cref(stop_flood), std::ref(fc), o.flood_max_requests);
        // The frames the server answers (wrong unit, unknown function) have been answered once
        // before the flood takes every free slot (during it a malformed client gets a slot only
        // now and then, and in a sanitizer build that may be never within the window).
        for (int w = 0; w < 500 && (fc.malformed_kinds_answered.load() & 0x30u) != 0x30u; ++w) sleep_s(0.01);
        sleep_s(0.05);
        for (int i = 0; i < o.flood_clients; ++i)
          flood.emplace_back(flood_client, server.bound_port(), i, std::cref(stop_flood), std::ref(fc), o.flood_max_requests);
        break;
      case Fault::can_errors:
        bus.error_frames_per_period = o.can_error_frames;
        bus.malformed_per_period = 2;
        break;
      case Fault::can_babble: bus.error_frames_per_period = o.can_babble_frames; break;
      case Fault::sensor_silent: bus.sensor_silent = true; break;
      case Fault::sensor_stale: bus.sensor_every = 20; break;
      case Fault::storage_full:
      case Fault::storage_full_other:
      case Fault::storage_eio:
      case Fault::storage_read_only:
      case Fault::storage_slow_fsync: storage_faults.set(o.fault, o.slow_fsync_ms); break;
      case Fault::none: break;
    }
    run_window(o.window_s, true, {});
    stop_flood = true;
    for (auto& t : flood) t.join();
    res.modbus_requests = fc.requests.load();
    {
      const auto s = state_phase();
      res.state_after_fault = fw::to_string(static_cast<fw::State>(s[0]));
      res.fault_reason_after_fault = fw::to_string(static_cast<fw::FaultReason>(s[2]));
    }
    bus.error_frames_per_period = 0;
    bus.malformed_per_period = 0;
    bus.sensor_silent = false;
    bus.sensor_every = 1;
    storage_faults.clear();

    // ---- recovery: the fault is gone; a loop fault is reset and the rotor lifted again -------
    window = 3;
    if (state_phase()[0] == static_cast<uint16_t>(fw::State::fault)) {
      sleep_s(0.2);  // the nodes are heard again
      try {
        lk::send_command(*link, k_arm_key, regs::op_reset_fault);
        sleep_s(0.05);
        res.relevitated = levitate();
      } catch (const std::exception&) {
        res.relevitated = false;
      }
    }
    run_window(o.recovery_s, true, {});
    // Events still waiting for a retry are written now that the storage works again (bounded).
    sleep_s(board.capture.post_trigger_s + 0.1);  // the last capture freezes its window
    auto unaccounted = [&] {
      const fw::StoreCounters k = writer.store_counters();
      return k.pending > 0 || capture.counters().events_frozen > k.written + k.refused + k.lost;
    };
    for (int i = 0; i < 500 && unaccounted(); ++i) sleep_s(0.02);
    const auto after = read_counters(*link);
    for (const auto& [k, v] : after) res.counters[k] = v - std::min(v, before.count(k) ? before.at(k) : 0);
    res.state_at_end = fw::to_string(static_cast<fw::State>(state_phase()[0]));
  } catch (...) {
    finish();
    throw;
  }
  finish();

  res.realtime = fifo.load();
  res.quiet = win[1].stats();
  res.faulted = win[2].stats();
  res.recovery = win[3].stats();
  const fw::CaptureCounters cc = capture.counters();
  const fw::StoreCounters sc = writer.store_counters();
  res.events_frozen = cc.events_frozen;
  res.capture_lost = cc.events_lost;
  res.written = sc.written;
  res.refused = sc.refused;
  res.dropped_oldest = sc.dropped_oldest;
  res.write_errors = sc.write_errors;
  res.retries = sc.retries;
  res.pending_at_end = sc.pending;
  res.writer_lost = sc.lost;
  res.events_lost = cc.events_lost + sc.lost;

  // ---- records torn: everything on disk, read back without the fault hook ----------------------
  {
    lx::FileStorage ev(dir + "/events"), wr(dir + "/wear");
    std::vector<uint8_t> bytes;
    std::string e;
    for (const std::string& name : ev.list()) {
      ++res.files_on_disk;
      fw::EventRecord rec;
      if (!ev.read(name, bytes, e) || !fw::decode_event(bytes, rec, e)) ++res.events_torn;
    }
    fw::WearStore again(wr, board.name);
    const fw::GenerationReport rep = again.open();
    res.wear_corrupt_slots = rep.corrupt_slots;
    res.wear_sequence = again.has_record() ? again.record().sequence : 0;
  }
  if (!o.keep_dir) std::filesystem::remove_all(dir);
  res.wall_s = since(t_start);
  return res;
}

}  // namespace amb::sil::faults
