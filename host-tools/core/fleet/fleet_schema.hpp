#pragma once
// The fleet store's schema, versioned: migration N takes a store from version N-1 to N,
// each in its own transaction (a store is never left between versions). Opening a store
// applies the pending migrations; a store newer than this program is refused.
//
// v1: machines; events (the .ambe file itself, its content hash, board metadata) with the
//     board's quick-look per aux bearing; wear records (AMBW) with the per-bearing figures;
//     fit and residual results (their JSON) per machine.
// v2: indexes for the per-machine time series (trend, nearest budget).
#include "host-tools/core/fleet/fleet_db.hpp"

namespace amb::host::fleet {

inline constexpr int k_schema_version = 2;  ///< what this program writes

/// Version of the store now (0: empty, no schema).
int schema_version(Database& db);

/// Apply migrations up to `target` (default: the latest). Throws DbError when the store is
/// newer than `target` or a migration fails (that migration is rolled back).
void migrate(Database& db, int target = k_schema_version);

}  // namespace amb::host::fleet
