// amb-host fetch: download drop events (and optionally the wear record) from a board over
// Modbus TCP. Resumable: partial downloads are kept as hidden .part files next to the output
// and continued by the next run; dropped connections are reconnected within a run. Every
// item is checked end to end against the CRC-32 the board lists.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware/persistence/crc32c.hpp"
#include "firmware/supervisory/register_addresses.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/link/board_link.hpp"

namespace {

namespace fs = std::filesystem;
namespace lk = amb::host::link;

struct Args {
  lk::LinkOptions link;
  std::string out_dir = ".";
  std::vector<std::string> names;
  bool list_only = false;
  std::string wear_out;
  bool json = false;
};

std::vector<uint8_t> read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_file(const fs::path& p, const std::vector<uint8_t>& d) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(d.data()), static_cast<std::streamsize>(d.size()));
  if (!out) throw std::runtime_error("cannot write " + p.string());
}

int run(const Args& a) {
  lk::ModbusLink link(a.link);
  const lk::BoardIdentity id = lk::read_identity(link);
  const auto events = lk::list_events(link);
  nlohmann::json j;
  j["board"] = id.board_name;
  j["events_on_board"] = events.size();
  nlohmann::json listed = nlohmann::json::array();
  for (const auto& e : events) listed.push_back({{"name", e.name}, {"bytes", e.size}, {"crc32c", e.crc32}});
  j["list"] = listed;
  if (a.list_only) {
    if (a.json) std::printf("%s\n", j.dump(2).c_str());
    else
      for (const auto& e : events) std::printf("%-34s %10u bytes  crc32c %08x\n", e.name.c_str(), e.size, e.crc32);
    return 0;
  }
  fs::create_directories(a.out_dir);
  lk::TransferStats total;
  nlohmann::json fetched = nlohmann::json::array();
  for (const auto& e : events) {
    if (!a.names.empty() && std::find(a.names.begin(), a.names.end(), e.name) == a.names.end()) continue;
    const fs::path final_path = fs::path(a.out_dir) / e.name;
    if (fs::exists(final_path)) {
      const auto have = read_file(final_path);
      if (have.size() == e.size && amb::fw::crc32c(have) == e.crc32) {
        fetched.push_back({{"name", e.name}, {"bytes", e.size}, {"crc32c", e.crc32}, {"status", "already_present"}});
        continue;
      }
    }
    const fs::path part = lk::part_path(a.out_dir, e);
    std::vector<uint8_t> data = fs::exists(part) ? read_file(part) : std::vector<uint8_t>{};
    lk::TransferStats s;
    // Persist progress every 64 blocks so that an interrupted run can resume.
    size_t since = 0;
    lk::download(link, e.index, e.crc32, e.size, data, s, [&](const std::vector<uint8_t>& d) {
      if (++since % 64 == 0) write_file(part, d);
    });
    write_file(part, data);
    fs::rename(part, final_path);
    total.bytes += s.bytes;
    total.wall_s += s.wall_s;
    total.reconnects += s.reconnects;
    total.requests += s.requests;
    fetched.push_back({{"name", e.name}, {"bytes", e.size}, {"crc32c", e.crc32}, {"status", "downloaded"},
                       {"resumed_from", s.resumed_from}, {"reconnects", s.reconnects}});
    if (!a.json)
      std::printf("fetched %s: %u bytes, crc32c %08x ok%s\n", e.name.c_str(), e.size, e.crc32,
                  s.resumed_from ? (" (resumed at " + std::to_string(s.resumed_from) + ")").c_str() : "");
  }
  if (!a.names.empty() && fetched.size() != a.names.size()) {
    std::fprintf(stderr, "amb-host fetch: error: %zu of the requested events are not on the board\n",
                 a.names.size() - fetched.size());
    return 1;
  }
  if (!a.wear_out.empty()) {
    const lk::WearSummary w = lk::read_wear_summary(link);
    if (!w.present) {
      std::fprintf(stderr, "amb-host fetch: error: the board holds no wear record\n");
      return 2;
    }
    std::vector<uint8_t> rec;
    lk::TransferStats s;
    const lk::BoardIdentity id2 = lk::read_identity(link);
    lk::download(link, amb::fw::regs::k_wear_item_index, w.crc32, id2.wear_record_bytes, rec, s);
    write_file(a.wear_out, rec);
    j["wear"] = {{"sequence", w.sequence}, {"crc32c", w.crc32}, {"bytes", rec.size()}, {"path", a.wear_out}};
    if (!a.json) std::printf("fetched wear record: sequence %u, crc32c %08x -> %s\n", w.sequence, w.crc32, a.wear_out.c_str());
  }
  j["fetched"] = fetched;
  j["bytes"] = total.bytes;
  j["wall_s"] = total.wall_s;
  j["throughput_kib_s"] = total.wall_s > 0 ? static_cast<double>(total.bytes) / 1024.0 / total.wall_s : 0.0;
  j["reconnects"] = total.reconnects;
  j["requests"] = total.requests;
  if (a.json) std::printf("%s\n", j.dump(2).c_str());
  else if (total.bytes)
    std::printf("%llu bytes in %.3f s (%.1f KiB/s), %d reconnect(s)\n", static_cast<unsigned long long>(total.bytes),
                total.wall_s, j["throughput_kib_s"].get<double>(), total.reconnects);
  return 0;
}

void add_link_options(CLI::App& sub, lk::LinkOptions& o) {
  sub.add_option("--host", o.host, "board address")->capture_default_str();
  namespace hc = amb::host::cli;
  hc::whole(sub.add_option("--port", o.port, "Modbus TCP port"), 1, 65535);
  hc::whole(sub.add_option("--unit", o.unit_id, "Modbus unit id"), 0, 255);
  hc::positive(sub.add_option("--timeout", o.response_timeout_s, "response timeout per request, s"), 600.0, "s");
  hc::whole(sub.add_option("--retries", o.max_retries, "reconnect attempts before giving up"), 0, 1000);
}

void declare(CLI::App& sub, Args& a) {
  add_link_options(sub, a.link);
  amb::host::cli::output_path(sub.add_option("--out", a.out_dir, "directory for the event files"));
  sub.add_option("--name", a.names, "fetch only these events (default: all)");
  sub.add_flag("--list", a.list_only, "only list the events on the board");
  amb::host::cli::output_file(sub.add_option("--wear", a.wear_out, "also download the stored wear record to this file"));
  sub.add_flag("--json", a.json, "print figures as JSON");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "fetch", "download drop events (resumable, CRC-checked) from a board over Modbus TCP", declare, run);

}  // namespace
