#pragma once
// The fleet store: every board event (.ambe), wear record (AMBW), fit and residual result
// (the --json output of amb-host fit / residual) of many machines in one database
// (fleet_db.hpp: SQLite file or PostgreSQL). Each file is imported in one transaction,
// keyed by the SHA-256 of its content: importing it again is a no-op, and an import killed
// part-way leaves the store as it was before that file.
//
// Life used per aux bearing: from the machine's wear records (the host's fitted life
// fraction, cumulative); a machine without wear records is shown with the board's
// quick-look life fractions summed over its events (source "quick_look").
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "host-tools/core/fleet/fleet_db.hpp"

namespace amb::host::fleet {

struct AddResult {
  std::string path;
  std::string kind;         ///< "event", "wear", "fit", "residual"
  std::string machine;
  std::string content_hash; ///< SHA-256 of the file
  bool added = false;       ///< false: it was already in the store
};

struct MachineSummary {
  std::string name, rig;
  std::int64_t events = 0, wear_records = 0, fits = 0, residuals = 0;
  std::int64_t last_event_number = -1;  ///< -1: no event
};

/// One point of a bearing's life curve.
struct TrendPoint {
  std::string machine;
  int bearing = 0;                ///< aux bearing index ([[rig.aux_bearing]] order)
  std::string source;             ///< "wear" (record sequence) or "quick_look" (event number)
  std::int64_t order = 0;         ///< wear: record sequence; quick_look: event number
  std::int64_t time_unix_s = 0;   ///< wear: when the host computed it (0 for quick-look points)
  double life_used_fraction = 0.0;///< cumulative, 1 = budget used up
};

/// Where one bearing stands now.
struct BearingStatus {
  std::string machine;
  int bearing = 0;
  std::string source;             ///< "wear" or "quick_look"
  double life_used_fraction = 0.0;
  double peak_force_n = 0.0;      ///< largest contact force seen (wear record, else the quick-looks'), N
  std::int64_t events = 0;        ///< events accounted (wear record's count, else events stored)
};

class FleetStore {
 public:
  /// Opens (fleet_db.hpp open_database) and migrates to the latest schema.
  explicit FleetStore(const std::string& url);
  explicit FleetStore(std::unique_ptr<Database> db);

  /// Import one file; the kind is told by its content (AMBE / AMBW magic, or JSON keys:
  /// friction_coefficient -> fit, effects_added -> residual). `machine`: overrides the
  /// board name an event or wear record carries; required for fit/residual JSON that does
  /// not name a "board". Throws std::invalid_argument naming the file and what is wrong
  /// (nothing is written then).
  AddResult add_file(const std::string& path, const std::string& machine = {});

  std::vector<MachineSummary> machines();
  /// Life curves, by machine, bearing, order. `machine` empty: all.
  std::vector<TrendPoint> trend(const std::string& machine = {});
  /// Every bearing's standing, nearest its budget first (ties: machine name, bearing).
  std::vector<BearingStatus> nearest_budget();
  /// Rows of `table` (events, event_bearings, wear_records, wear_bearings, results, machines).
  std::int64_t count(const std::string& table);

  Database& db() { return *db_; }

 private:
  std::int64_t machine_id(const std::string& name, const std::string& rig);
  std::unique_ptr<Database> db_;
};

}  // namespace amb::host::fleet
