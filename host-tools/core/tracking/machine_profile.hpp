#pragma once
// Machine profile for `amb-host track-speed --profile FILE`: what is known about a machine's
// shaft speed before looking at a record (docs/tracking.md "Machine profiles"). A small TOML:
//
//   schema = "amb-machine/1"
//   name = "windturbine-hss"                 # free text
//   [speed]
//   min_hz = 10.0                            # lowest shaft speed expected, Hz
//   max_hz = 40.0                            # highest shaft speed expected, Hz
//   max_accel_hz_per_s = 2.0                 # largest |d speed/dt|, Hz/s
//   [orders]
//   comb = "discover"                        # or an array of orders, e.g. [1, 2, 3, 4]
//
// Every key is checked at load; an unknown key or a value out of range is an error that names
// the key (a typo must not silently fall back to a default).
#include <string>
#include <string_view>
#include <vector>

namespace amb::host {

struct MachineProfile {
  std::string name = "default";
  double min_speed_hz = 8.0;            ///< lowest shaft speed expected, Hz; [0.1, max)
  double max_speed_hz = 300.0;          ///< highest shaft speed expected, Hz; (min, 5000]
  double max_accel_hz_per_s = 150.0;    ///< largest |d speed/dt|, Hz/s; (0, 1e5]
  bool discover_orders = true;          ///< true: orders from the record (order_discovery.hpp)
  std::vector<double> orders;           ///< the comb when discover_orders is false; 1..8 values in (0, 100]
  /// true when the speed range comes from a profile file. The built-in default (false) knows
  /// nothing about the machine: any second, unrelated line family in its wide range makes the
  /// discovery ambiguous (every update lost) instead of guessing which family is the shaft.
  bool from_file = false;
};

/// The profile used when none is given: wide speed range, orders discovered.
MachineProfile default_machine_profile();

/// Parse a profile. Throws std::invalid_argument("<source>: <key>: <what>") on any error.
MachineProfile parse_machine_profile(std::string_view toml_text, const std::string& source);

/// Read and parse a profile file. Throws std::invalid_argument naming the file and key.
MachineProfile load_machine_profile(const std::string& path);

}  // namespace amb::host
