#include "host-tools/core/sweep/sweep_acquire.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "firmware/persistence/crc32c.hpp"
#include "firmware/sil/sil_sweep.hpp"
#include "firmware/supervisory/register_addresses.hpp"
#include "host-tools/core/link/board_link.hpp"
#include "host-tools/core/sweep/sweep_event.hpp"

namespace amb::host::sweep {

namespace regs = fw::regs;
namespace fs = std::filesystem;

namespace {

std::string write_event(const std::string& dir, const std::string& name, const std::vector<uint8_t>& bytes) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw AcquireError("cannot create " + dir + ": " + ec.message());
  const std::string path = (fs::path(dir) / name).string();
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw AcquireError("cannot write " + tmp);
  }
  fs::rename(tmp, path, ec);
  if (ec) throw AcquireError("cannot rename " + tmp + " to " + path + ": " + ec.message());
  return path;
}

std::string progress_line(const char* where, unsigned state, int axis, unsigned axis_index, unsigned axes_total,
                          unsigned period, unsigned periods, double t_s) {
  char b[200];
  static const char* names[] = {"idle", "settling", "recording", "storing"};
  std::snprintf(b, sizeof b, "%s t=%.2f s: %s, axis %d (%u of %u), period %u of %u", where, t_s,
                state < 4 ? names[state] : "?", axis, axis_index + 1, axes_total, period + 1, periods);
  return b;
}

AcquireResult finish(const std::string& out_dir, const std::string& name, const std::vector<uint8_t>& bytes) {
  AcquireResult r;
  std::string err;
  if (!decode_sweep_record(bytes, r.record, err)) throw AcquireError(name + ": " + err);
  r.event_name = name;
  r.event_bytes = bytes.size();
  r.event_path = write_event(out_dir, name, bytes);
  return r;
}

}  // namespace

AcquireResult acquire_sweep_sil(const board::BoardConfig& board, const AcquireOptions& o) {
  sil::SilSweepOptions so;
  so.noise_seed = o.noise_seed;
  so.spin = o.spin;
  so.timeout_s = o.timeout_s;
  if (o.progress) {
    so.progress = [&](const fw::SweepStatus& s, double t) {
      o.progress(progress_line("sim", static_cast<unsigned>(s.state), s.axis, s.axis_index, s.axes_total, s.period,
                               s.periods_per_axis, t));
    };
  }
  const sil::SilSweepOutcome out = sil::run_sil_sweep(board, so);
  if (!out.stored) throw AcquireError("board " + board.name + ": " + out.error);
  AcquireResult r = finish(o.out_dir, out.event_name, out.event_bytes);
  r.refusals = out.status.refusals;
  r.aborts = out.status.aborts;
  return r;
}

AcquireResult acquire_sweep_modbus(const link::LinkOptions& lo, uint32_t arm_key, const AcquireOptions& o) {
  link::ModbusLink ml(lo);
  const link::BoardIdentity id = link::read_identity(ml);
  std::vector<uint16_t> s(regs::sweep_end - regs::sweep);
  auto u32 = [&](uint16_t at) { return link::u32_at(s, at - regs::sweep); };
  auto u16 = [&](uint16_t at) { return s[at - regs::sweep]; };
  ml.read(regs::sweep, s);
  if (u16(regs::sweep_config_refusal) != 0)
    throw AcquireError("board " + id.board_name + " cannot sweep: " +
                       fw::to_string(static_cast<fw::SweepRefusal>(u16(regs::sweep_config_refusal))));
  const uint32_t stored_before = u32(regs::sweep_events_stored);
  const uint32_t refusals_before = u32(regs::sweep_refusals);
  try {
    link::send_command(ml, arm_key, regs::k_command_sweep_start);
  } catch (const link::ModbusException& e) {
    ml.read(regs::sweep, s);
    const auto why = static_cast<fw::SweepRefusal>(u16(regs::sweep_last_refusal));
    throw AcquireError("board " + id.board_name + " refused the sweep (Modbus exception " + std::to_string(e.code()) +
                       (u32(regs::sweep_refusals) > refusals_before ? std::string(", reason ") + fw::to_string(why) : "") +
                       ")");
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  while (true) {
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll_s));
    ml.read(regs::sweep, s);
    const uint16_t axis = u16(regs::sweep_axis);
    if (o.progress)
      o.progress(progress_line(id.board_name.c_str(), u16(regs::sweep_state), axis == 0xFFFF ? -1 : axis,
                               u16(regs::sweep_axis_index), u16(regs::sweep_axes_total), u16(regs::sweep_period),
                               u16(regs::sweep_periods_per_axis), elapsed()));
    if (u32(regs::sweep_events_stored) > stored_before) break;
    if (elapsed() > o.timeout_s) {
      link::send_command(ml, arm_key, regs::k_command_sweep_abort);
      throw AcquireError("board " + id.board_name + ": no sweep event stored within " + std::to_string(o.timeout_s) +
                         " s (abort sent)");
    }
  }
  char name[32];
  std::snprintf(name, sizeof name, "event_%08u.ambe", u32(regs::sweep_last_event));
  link::EventInfo info;
  bool found = false;
  for (const link::EventInfo& e : link::list_events(ml))
    if (e.name == name) {
      info = e;
      found = true;
    }
  if (!found) throw AcquireError("board " + id.board_name + ": sweep event " + name + " is not in the event list");
  std::vector<uint8_t> bytes;
  link::TransferStats ts;
  link::download(ml, info.index, info.crc32, info.size, bytes, ts);
  if (fw::crc32c(bytes) != info.crc32) throw AcquireError(std::string("sweep event ") + name + ": CRC-32C mismatch after download");
  AcquireResult r = finish(o.out_dir, name, bytes);
  r.refusals = u32(regs::sweep_refusals);
  r.aborts = u32(regs::sweep_aborts);
  return r;
}

}  // namespace amb::host::sweep
