#include "host-tools/core/fleet/fleet_schema.hpp"

#include <string>
#include <vector>

namespace amb::host::fleet {
namespace {

// Index i: migration to version i + 1. Never edit a released migration; add one.
const std::vector<std::string> k_migrations = {
    // v1
    R"(CREATE TABLE machines (
  id {id},
  name TEXT NOT NULL UNIQUE,
  rig TEXT NOT NULL DEFAULT '');
CREATE TABLE events (
  id {id},
  content_hash TEXT NOT NULL UNIQUE,
  machine_id BIGINT NOT NULL REFERENCES machines(id),
  event_number BIGINT NOT NULL,
  trigger_t_ns BIGINT NOT NULL,
  cause TEXT NOT NULL,
  speed_at_trigger_hz DOUBLE PRECISION,
  samples BIGINT NOT NULL,
  rate_hz DOUBLE PRECISION NOT NULL,
  phase_b_fault TEXT NOT NULL DEFAULT '',
  source TEXT NOT NULL,
  bytes {blob} NOT NULL);
CREATE TABLE event_bearings (
  event_id BIGINT NOT NULL REFERENCES events(id),
  position BIGINT NOT NULL,
  quick_look_valid BIGINT NOT NULL,
  peak_force_n DOUBLE PRECISION NOT NULL,
  life_fraction DOUBLE PRECISION NOT NULL,
  contact_time_s DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (event_id, position));
CREATE TABLE wear_records (
  id {id},
  content_hash TEXT NOT NULL UNIQUE,
  machine_id BIGINT NOT NULL REFERENCES machines(id),
  sequence BIGINT NOT NULL,
  updated_unix_s BIGINT NOT NULL,
  event_count BIGINT NOT NULL,
  life_model TEXT NOT NULL,
  friction_coefficient DOUBLE PRECISION NOT NULL,
  source TEXT NOT NULL);
CREATE TABLE wear_bearings (
  wear_id BIGINT NOT NULL REFERENCES wear_records(id),
  position BIGINT NOT NULL,
  life_used_fraction DOUBLE PRECISION NOT NULL,
  friction_energy_j DOUBLE PRECISION NOT NULL,
  peak_force_n DOUBLE PRECISION NOT NULL,
  swing_s DOUBLE PRECISION NOT NULL,
  forward_rub_s DOUBLE PRECISION NOT NULL,
  backward_rub_s DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (wear_id, position));
CREATE TABLE results (
  id {id},
  content_hash TEXT NOT NULL UNIQUE,
  machine_id BIGINT NOT NULL REFERENCES machines(id),
  kind TEXT NOT NULL,
  event_ref TEXT NOT NULL DEFAULT '',
  friction_coefficient DOUBLE PRECISION,
  cost DOUBLE PRECISION,
  converged BIGINT,
  whirl TEXT NOT NULL DEFAULT '',
  verdict TEXT NOT NULL DEFAULT '',
  rms_before DOUBLE PRECISION,
  rms_after DOUBLE PRECISION,
  document TEXT NOT NULL,
  source TEXT NOT NULL);)",
    // v2
    R"(CREATE INDEX events_machine ON events (machine_id, event_number);
CREATE INDEX wear_machine ON wear_records (machine_id, sequence);
CREATE INDEX results_machine ON results (machine_id, kind);)",
};

}  // namespace

int schema_version(Database& db) {
  db.script("CREATE TABLE IF NOT EXISTS schema_version (version BIGINT NOT NULL)");
  const auto rows = db.query("SELECT version FROM schema_version");
  return rows.empty() ? 0 : static_cast<int>(as_int(rows[0][0]));
}

void migrate(Database& db, int target) {
  if (target < 0 || target > static_cast<int>(k_migrations.size()))
    throw DbError("fleet store: no schema version " + std::to_string(target));
  const int now = schema_version(db);
  if (now > target)
    throw DbError("fleet store: schema version " + std::to_string(now) + " is newer than this program's (" + std::to_string(target) + ")");
  for (int v = now + 1; v <= target; ++v) {
    Transaction t(db);
    // Re-read inside the transaction: another process may have migrated meanwhile.
    const auto rows = db.query("SELECT version FROM schema_version");
    const int cur = rows.empty() ? 0 : static_cast<int>(as_int(rows[0][0]));
    if (cur >= v) {
      t.commit();
      continue;
    }
    db.script(k_migrations[static_cast<size_t>(v - 1)]);
    if (rows.empty()) db.query("INSERT INTO schema_version (version) VALUES (?)", {std::int64_t{v}});
    else db.query("UPDATE schema_version SET version = ?", {std::int64_t{v}});
    t.commit();
  }
}

}  // namespace amb::host::fleet
