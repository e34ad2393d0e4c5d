#pragma once
// Synthetic fleet files for the fleet-store tests: board events (AMBE v2, encoded by the
// firmware's own encoder) from several boards with quick-look loads, wear records (AMBW,
// the firmware's encoder) with growing life fractions, and fit / residual JSON results.
#include <filesystem>
#include <string>
#include <vector>

#include "host-tools/core/fleet/fleet_store.hpp"

namespace amb::test::fleet {

struct FleetFiles {
  std::vector<std::string> events;   ///< 100 .ambe files
  std::vector<std::string> wear;     ///< wear records (some machines only)
  std::vector<std::string> results;  ///< fit and residual JSON
  std::vector<std::string> all() const;
};

/// Write the files under `dir` (created). `samples_per_event`: loop samples in each event.
FleetFiles make_fleet_files(const std::filesystem::path& dir, int samples_per_event = 2000);

/// The answers of every query of the store as text (doubles at round-trip precision): what
/// must be identical between engines.
std::string query_dump(host::fleet::FleetStore& store);

/// A fresh directory under the system temp dir.
std::filesystem::path fresh_dir(const std::string& name);

}  // namespace amb::test::fleet
