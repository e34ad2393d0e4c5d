// amb-host writeback: send a wear record (AMBW v1) to a board over Modbus TCP. The board
// validates format, CRC, board name and sequence number before it replaces its stored record
// (power-loss safe); the transfer resumes after dropped connections. The commit is a command:
// it is armed with the board's key ([comms.modbus] arm_key of its board file: --board, or
// --arm-key, or the environment variable AMB_ARM_KEY).
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware/board/board.hpp"
#include "firmware/persistence/crc32c.hpp"
#include "firmware/persistence/wear_store.hpp"
#include "firmware/wear/wear_record.hpp"
#include "host-tools/amb-host/cli_checks.hpp"
#include "host-tools/amb-host/command.hpp"
#include "host-tools/core/link/board_link.hpp"
#include "host-tools/core/wear/wear_record_file.hpp"

namespace {

namespace lk = amb::host::link;

struct Args {
  lk::LinkOptions link;
  std::string record_path;
  bool renumber = false;
  bool json = false;
  std::string arm_key;  ///< as given (decimal or 0x hex)
  std::string board;    ///< board name or file to take the arm key from
};

int run(const Args& a) {
  // The record first: a bad file is named as such, whatever else is missing.
  amb::fw::WearRecord rec;
  try {
    rec = amb::host::wear::read_wear_record_file(a.record_path);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "amb-host writeback: error: %s\n", e.what());
    return 1;
  }
  // The file's bytes: the decoder accepts only what the encoder writes (fuzz_wear_ambw).
  std::vector<uint8_t> bytes = amb::fw::encode_wear_record(rec);
  const uint32_t key = amb::host::cli::arm_key(
      a.arm_key, a.board,
      "the commit needs the board's arm key: --board NAME|FILE (its [comms.modbus] arm_key), --arm-key KEY or AMB_ARM_KEY");
  lk::ModbusLink link(a.link);
  const lk::BoardIdentity id = lk::read_identity(link);
  const lk::WearSummary before = lk::read_wear_summary(link);
  const uint32_t next = before.present ? before.sequence + 1 : 1;
  if (rec.sequence != next) {
    if (!a.renumber) {
      std::fprintf(stderr,
                   "amb-host writeback: error: record sequence %u, the board expects %u (use --renumber to "
                   "re-sequence it)\n", rec.sequence, next);
      return 1;
    }
    rec.sequence = next;
    bytes = amb::fw::encode_wear_record(rec);
  }
  if (rec.board_name != id.board_name) {
    std::fprintf(stderr, "amb-host writeback: error: record is for board '%s', the board is '%s'\n",
                 rec.board_name.c_str(), id.board_name.c_str());
    return 1;
  }
  const lk::WriteBackOutcome o = lk::write_back(link, bytes, key);
  const lk::WearSummary after = lk::read_wear_summary(link);
  const bool ok = (o.result_name == "accepted" || o.already_stored) && after.present && after.crc32 == amb::fw::crc32c(bytes);
  nlohmann::json j{{"board", id.board_name},
                   {"result", o.result_name},
                   {"sequence", rec.sequence},
                   {"stored_sequence", after.sequence},
                   {"crc32c", amb::fw::crc32c(bytes)},
                   {"stored_crc32c", after.crc32},
                   {"verified", ok},
                   {"bytes", bytes.size()},
                   {"resumed_from", o.stats.resumed_from},
                   {"wall_s", o.stats.wall_s},
                   {"reconnects", o.stats.reconnects},
                   {"generation", after.generation},
                   {"commit_attempts", o.commit_attempts}};
  if (a.json) std::printf("%s\n", j.dump(2).c_str());
  else
    std::printf("writeback %s: %s (sequence %u, crc32c %08x, %zu bytes, %.3f s, %d reconnect(s))\n",
                a.record_path.c_str(), o.result_name.c_str(), rec.sequence, amb::fw::crc32c(bytes), bytes.size(),
                o.stats.wall_s, o.stats.reconnects);
  return ok ? 0 : 2;
}

void declare(CLI::App& sub, Args& a) {
  namespace hc = amb::host::cli;
  hc::input_file(sub.add_option("record", a.record_path, "encoded wear record (AMBW v1)")->required(), "wear-record");
  sub.add_option("--host", a.link.host, "board address")->capture_default_str();
  hc::whole(sub.add_option("--port", a.link.port, "Modbus TCP port"), 1, 65535);
  hc::whole(sub.add_option("--unit", a.link.unit_id, "Modbus unit id"), 0, 255);
  hc::positive(sub.add_option("--timeout", a.link.response_timeout_s, "response timeout per request, s"), 600.0, "s");
  hc::whole(sub.add_option("--retries", a.link.max_retries, "reconnect attempts before giving up"), 0, 1000);
  sub.add_flag("--renumber", a.renumber, "set the record's sequence to the one the board expects");
  hc::input_file(sub.add_option("--board", a.board, "board name or file whose [comms.modbus] arm_key arms the commit"), "board");
  sub.add_option("--arm-key", a.arm_key, "the board's arm key (decimal or 0x hex; default: --board, then AMB_ARM_KEY)");
  sub.add_flag("--json", a.json, "print figures as JSON");
}

const amb::host::Registration reg = amb::host::make_command<Args>(
    "writeback", "write a wear record back to a board over Modbus TCP (validated and persisted there)", declare, run);

}  // namespace
