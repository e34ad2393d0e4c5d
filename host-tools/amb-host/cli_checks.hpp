#pragma once
// The checks every amb-host option goes through (one rule for all sub-commands): numbers are
// finite and in the option's range, input files exist, are regular files and are not empty,
// and each check's error names the option as the user typed it (CLI11 prefixes it). The
// checks also record what they know about an option (range, file kind, output) for the
// command table: --help, the man page and the bad-input sweep (tests/cli) read it from there.
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "firmware/common/cli_number.hpp"

namespace amb::host::cli {

/// What the checks know about one option.
struct OptionInfo {
  std::optional<amb::cli::NumberRange> range;  ///< numeric option: its allowed values
  std::string file_kind;                       ///< input file: what it must hold (e.g. "ambe", "mat", "board")
  bool output = false;                         ///< a file or directory the command writes
  bool output_file = false;                    ///< a file (or file stem) whose folder must already exist
};

/// Numeric option: finite, inside `r`; the default value is shown in --help. Returns `o`.
CLI::Option* number(CLI::Option* o, amb::cli::NumberRange r);
/// Shorthands: a real number in [lo, hi] (unit for the help), and a whole number in [lo, hi].
CLI::Option* real(CLI::Option* o, double lo, double hi, const char* unit = "");
CLI::Option* positive(CLI::Option* o, double hi, const char* unit = "");  ///< (0, hi]
CLI::Option* whole(CLI::Option* o, double lo, double hi);

/// Input file of a kind (shown in --help and the man page; the sweep feeds it wrong kinds):
/// "ambe" (board event), "event" (AMBE or measured event .json/.csv/stem), "measured-event",
/// "mat", "board" (name or TOML file), "profile", "envelope-spec", "wear-record",
/// "hybrid-model". Kinds "board" accepts an embedded board name as well as a file; "event"
/// and "measured-event" accept a stem whose .json exists.
CLI::Option* input_file(CLI::Option* o, const std::string& kind);
/// A file or directory the command writes (recorded for the sweep, which checks that bad
/// input writes nothing). The command creates a directory output, with its parents.
CLI::Option* output_path(CLI::Option* o);
/// A file, or a file stem (STEM.csv, STEM.json), the command writes: its folder must exist,
/// checked at parse, before any work (a fit or a simulation is not run to find out that its
/// result cannot be written). Recorded like output_path.
CLI::Option* output_file(CLI::Option* o);

/// A message from an options struct's check() written with the names the user typed:
/// each `internal` field name (e.g. "stft.nfft", "doe_points") replaced by its option
/// ("--nfft", "--doe"). Pairs are applied in order (put "stft.window_s" before "window_s").
std::string in_option_names(std::string message,
                            std::initializer_list<std::pair<const char*, const char*>> internal_to_option);

/// What the checks recorded for `o` (nullptr: nothing).
const OptionInfo* info(const CLI::Option* o);

/// The arm key a Modbus command needs: `option_value` (--arm-key, decimal or 0x hex) when given,
/// else the [comms.modbus] arm_key of `board` (a board name or file) when given, else the
/// environment's AMB_ARM_KEY. Throws std::invalid_argument naming the source and what is wrong,
/// or with `when_missing` (which says where a key can come from) when none is given.
uint32_t arm_key(const std::string& option_value, const std::string& board, const std::string& when_missing);

}  // namespace amb::host::cli
