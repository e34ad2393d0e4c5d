#pragma once
// Strict reading of TOML tables: every key read is range-checked, every key not read is an
// error (Klipper-style). Used only by the board loader.
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace amb::board {

class TableReader {
 public:
  TableReader(const toml::table& table, std::string path, const std::string& source);

  /// Required number in [lo, hi].
  double number(const std::string& key, double lo, double hi);
  /// Optional number in [lo, hi]; `fallback` when absent.
  double number_or(const std::string& key, double fallback, double lo, double hi);
  /// Optional integer in [lo, hi].
  long long integer_or(const std::string& key, long long fallback, long long lo, long long hi);
  bool boolean_or(const std::string& key, bool fallback);
  std::string string(const std::string& key);
  std::string string_or(const std::string& key, const std::string& fallback);
  /// Required array of numbers, each in [lo, hi], with exactly `count` entries (count < 0: any).
  std::vector<double> numbers(const std::string& key, int count, double lo, double hi);
  /// Required sub-table.
  TableReader table(const std::string& key);
  bool has(const std::string& key) const;
  /// Array of tables with between min_count and max_count entries (absent = empty if min 0).
  std::vector<TableReader> tables(const std::string& key, int min_count, int max_count);
  /// Array of inline tables (e.g. notches = [{...}, {...}]).
  std::vector<TableReader> inline_tables(const std::string& key, int min_count, int max_count);
  /// All string-valued entries of this table (for [assumed]); marks them read.
  std::vector<std::pair<std::string, std::string>> string_entries();
  /// Throws if a key was present but never read.
  void finish();

  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  const toml::node* find(const std::string& key);
  std::string key_path(const std::string& key) const;

  const toml::table* table_;
  std::string path_;
  const std::string* source_;
  std::set<std::string> read_;
};

}  // namespace amb::board
