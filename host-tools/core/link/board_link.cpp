#include "host-tools/core/link/board_link.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "firmware/persistence/crc32c.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/supervisory/register_addresses.hpp"

namespace amb::host::link {

namespace regs = amb::fw::regs;

namespace {
double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

BoardIdentity read_identity(ModbusLink& link) {
  std::vector<uint16_t> r(regs::identity_end - regs::identity);
  link.read(regs::identity, r);
  if (r[regs::magic] != regs::k_magic_value)
    throw std::runtime_error("not an AMB board (identity register reads 0x" + std::to_string(r[regs::magic]) + ")");
  BoardIdentity id;
  id.map_version = r[regs::map_version];
  id.firmware_version = r[regs::firmware_version];
  id.loop_rate_hz = r[regs::loop_rate_hz];
  id.wear_record_bytes = r[regs::wear_record_bytes];
  id.block_bytes = r[regs::download_block_bytes];
  id.chunk_bytes = r[regs::writeback_chunk_bytes];
  id.board_name = string_at(r, regs::board_name, 16);
  std::vector<uint16_t> s(4);
  link.read(regs::state, s);
  id.state = s[0];
  id.fault = s[2];
  id.state_flags = s[3];
  return id;
}

std::vector<EventInfo> list_events(ModbusLink& link) {
  // The list may change while it is read: read it again until the version holds still.
  for (int attempt = 0; attempt < 5; ++attempt) {
    std::vector<uint16_t> head(2);
    link.read(regs::event_count, head);
    std::vector<EventInfo> out;
    for (uint16_t i = 0; i < head[0]; ++i) {
      const std::vector<uint16_t> sel{i};
      std::vector<uint16_t> e(regs::event_entry_end - regs::event_list_version);
      link.write_read(regs::event_browse_index, sel, regs::event_list_version, e);
      if (e[0] != head[1]) break;
      EventInfo info;
      info.index = i;
      info.size = u32_at(e, regs::event_entry_size - regs::event_list_version);
      info.crc32 = u32_at(e, regs::event_entry_crc - regs::event_list_version);
      info.name = string_at(e, regs::event_entry_name - regs::event_list_version, 16);
      out.push_back(info);
    }
    if (out.size() == head[0]) return out;
  }
  throw std::runtime_error("the board's event list kept changing while it was read");
}

WearSummary read_wear_summary(ModbusLink& link) {
  std::vector<uint16_t> r(regs::wear_end - regs::wear_present);
  link.read(regs::wear_present, r);
  WearSummary w;
  w.present = r[0] != 0;
  w.sequence = u32_at(r, 1);
  w.event_count = u32_at(r, 3);
  w.crc32 = u32_at(r, 5);
  w.generation = u32_at(r, regs::wear_generation - regs::wear_present);
  w.corrupt_at_start = r[regs::wear_corrupt_at_start - regs::wear_present];
  return w;
}

void download(ModbusLink& link, uint16_t index, uint32_t crc32, uint32_t size, std::vector<uint8_t>& data,
              TransferStats& stats, const std::function<void(const std::vector<uint8_t>&)>& checkpoint) {
  const double t0 = now_s();
  const int reconnects0 = link.reconnects();
  const uint64_t requests0 = link.requests();
  const size_t block_bytes = regs::k_block_bytes;
  data.resize(std::min<size_t>(data.size(), size) / block_bytes * block_bytes);
  stats.resumed_from = data.size();
  const uint32_t blocks = (size + block_bytes - 1) / block_bytes;
  std::vector<uint16_t> r(regs::dl_end - regs::dl_status);
  int crc_retries = 0;
  for (uint32_t b = static_cast<uint32_t>(data.size() / block_bytes); b < blocks;) {
    const std::vector<uint16_t> sel{index, static_cast<uint16_t>(crc32 >> 16), static_cast<uint16_t>(crc32),
                                    static_cast<uint16_t>(b >> 16), static_cast<uint16_t>(b)};
    // Select and read the block in one round trip.
    link.write_read(regs::dl_select, sel, regs::dl_status, r);
    const uint16_t status = r[0];
    if (status == regs::dl_stale) throw std::runtime_error("the item changed on the board (stale selection); list again");
    if (status != regs::dl_ok) throw std::runtime_error("board refused block " + std::to_string(b) + " (status " + std::to_string(status) + ")");
    const uint16_t n = r[1];
    const uint32_t block_crc = u32_at(r, 2);
    if (u32_at(r, regs::dl_block - regs::dl_status) != b || n > block_bytes ||
        u32_at(r, regs::dl_total_bytes - regs::dl_status) != size)
      throw std::runtime_error("board answered for another block or size");
    std::vector<uint8_t> bytes(n);
    for (size_t i = 0; i < n; ++i) {
      const uint16_t w = r[regs::dl_data - regs::dl_status + i / 2];
      bytes[i] = static_cast<uint8_t>(i % 2 == 0 ? w >> 8 : w & 0xFF);
    }
    if (fw::crc32c(bytes) != block_crc) {
      ++stats.block_crc_errors;
      if (++crc_retries > 5) throw std::runtime_error("block " + std::to_string(b) + " keeps failing its CRC");
      continue;
    }
    data.insert(data.end(), bytes.begin(), bytes.end());
    stats.bytes += n;
    ++b;
    if (checkpoint) checkpoint(data);
  }
  stats.wall_s += now_s() - t0;
  stats.reconnects += link.reconnects() - reconnects0;
  stats.requests += link.requests() - requests0;
  if (data.size() != size || fw::crc32c(data) != crc32)
    throw std::runtime_error("downloaded item fails its end-to-end CRC-32 (expected " + std::to_string(crc32) + ")");
}

void arm(ModbusLink& link, uint32_t arm_key, uint16_t operation) {
  const std::vector<uint16_t> a{static_cast<uint16_t>(arm_key >> 16), static_cast<uint16_t>(arm_key), operation};
  try {
    link.write(regs::arm, a);
  } catch (const ModbusException& e) {
    if (e.code() == 3) throw ModbusException(3, "the board refused the arm sequence: wrong arm key (its board file's [comms.modbus] arm_key)");
    if (e.code() == 1) throw ModbusException(1, "the board takes no commands over Modbus (no [comms.modbus] arm_key in its board file)");
    throw;
  }
}

void send_command(ModbusLink& link, uint32_t arm_key, uint16_t command) {
  arm(link, arm_key, command);
  link.write(regs::command, std::vector<uint16_t>{command});
}

WriteBackOutcome write_back(ModbusLink& link, const std::vector<uint8_t>& record, uint32_t arm_key) {
  WriteBackOutcome out;
  const double t0 = now_s();
  const int reconnects0 = link.reconnects();
  const uint64_t requests0 = link.requests();
  const uint32_t size = static_cast<uint32_t>(record.size());
  const uint32_t crc = fw::crc32c(record);
  const std::vector<uint16_t> begin{regs::wb_begin, static_cast<uint16_t>(size >> 16), static_cast<uint16_t>(size),
                                    static_cast<uint16_t>(crc >> 16), static_cast<uint16_t>(crc)};
  std::vector<uint16_t> st(regs::wb_status_end - regs::wb_control);
  auto read_status = [&] { link.read(regs::wb_control, st); };
  // Begin (or resume the board's session for these very bytes), then send from where it is.
  link.write(regs::wb_control, begin);
  read_status();
  out.stats.resumed_from = u32_at(st, regs::wb_received - regs::wb_control);
  for (;;) {
    read_status();
    uint32_t at = u32_at(st, regs::wb_received - regs::wb_control);
    if (st[0] == regs::wb_idle) {  // the session was lost (board restarted): begin again
      link.write(regs::wb_control, begin);
      continue;
    }
    if (at >= size) break;
    while (at < size) {
      const uint32_t n = std::min<uint32_t>(regs::k_chunk_bytes, size - at);
      std::vector<uint16_t> chunk{static_cast<uint16_t>(at >> 16), static_cast<uint16_t>(at), static_cast<uint16_t>(n)};
      for (uint32_t i = 0; i < n; i += 2)
        chunk.push_back(static_cast<uint16_t>(record[at + i] << 8 | (i + 1 < n ? record[at + i + 1] : 0)));
      try {
        link.write(regs::wb_chunk, chunk);
      } catch (const ModbusException&) {
        break;  // out of step with the board (e.g. it lost the session): re-read its state
      }
      at += n;
      out.stats.bytes += n;
    }
  }
  int commit_error = 0;
  for (int attempt = 0; attempt < 3; ++attempt) {
    commit_error = 0;
    ++out.commit_attempts;
    arm(link, arm_key, regs::op_wear_commit);  // a wrong key is the caller's error: thrown
    try {
      link.write(regs::wb_control, std::vector<uint16_t>{regs::wb_commit});
    } catch (const ModbusException& e) {
      commit_error = e.code();
    }
    read_status();
    // The board ran the commit unless it refused it before (not armed: 1) or its storage
    // failed (4: the session stays complete, the old record stays the newest).
    if (st[0] != regs::wb_complete || (commit_error != 1 && commit_error != 4)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  out.result = st[regs::wb_result - regs::wb_control];
  out.stored_sequence = u32_at(st, regs::wb_stored_sequence - regs::wb_control);
  // A commit whose reply was lost and that was retried is refused as stale, and so is a
  // record the board already holds: either way the board now holds exactly these bytes.
  if (commit_error != 0 && out.result == static_cast<uint16_t>(fw::WriteBackResult::stale_sequence)) {
    const WearSummary w = read_wear_summary(link);
    if (w.present && w.crc32 == crc) out.already_stored = true;
  }
  out.result_name = out.already_stored ? "already_stored" : fw::to_string(static_cast<fw::WriteBackResult>(out.result));
  out.stats.wall_s = now_s() - t0;
  out.stats.reconnects = link.reconnects() - reconnects0;
  out.stats.requests = link.requests() - requests0;
  return out;
}

std::string part_path(const std::string& dir, const EventInfo& e) {
  char crc[16];
  std::snprintf(crc, sizeof crc, "%08x", e.crc32);
  return dir + "/." + e.name + "." + crc + ".part";
}

}  // namespace amb::host::link
