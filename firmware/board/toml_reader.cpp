#include "firmware/board/toml_reader.hpp"

#include <cmath>
#include <sstream>

#include "firmware/board/board.hpp"

namespace amb::board {
namespace {
std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}
std::string range(double lo, double hi) { return "[" + fmt(lo) + ", " + fmt(hi) + "]"; }
}  // namespace

TableReader::TableReader(const toml::table& table, std::string path, const std::string& source)
    : table_(&table), path_(std::move(path)), source_(&source) {}

std::string TableReader::key_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void TableReader::fail(const std::string& key, const std::string& message) const {
  throw BoardError(*source_, key_path(key), message);
}

const toml::node* TableReader::find(const std::string& key) {
  const toml::node* n = table_->get(key);
  if (n) read_.insert(key);
  return n;
}

bool TableReader::has(const std::string& key) const { return table_->contains(key); }

double TableReader::number(const std::string& key, double lo, double hi) {
  const toml::node* n = find(key);
  if (!n) fail(key, "missing; expected a number in " + range(lo, hi));
  std::optional<double> v = n->is_number() ? n->value<double>() : std::nullopt;
  if (!v) fail(key, "must be a number in " + range(lo, hi));
  if (!std::isfinite(*v) || *v < lo || *v > hi)
    fail(key, "value " + fmt(*v) + " is out of range; allowed " + range(lo, hi));
  return *v;
}

double TableReader::number_or(const std::string& key, double fallback, double lo, double hi) {
  if (!has(key)) return fallback;
  return number(key, lo, hi);
}

long long TableReader::integer_or(const std::string& key, long long fallback, long long lo,
                                  long long hi) {
  const toml::node* n = find(key);
  if (!n) return fallback;
  if (!n->is_integer())
    fail(key, "must be an integer in " + range(static_cast<double>(lo), static_cast<double>(hi)));
  long long v = n->as_integer()->get();
  if (v < lo || v > hi)
    fail(key, "value " + std::to_string(v) + " is out of range; allowed [" + std::to_string(lo) +
                  ", " + std::to_string(hi) + "]");
  return v;
}

bool TableReader::boolean_or(const std::string& key, bool fallback) {
  const toml::node* n = find(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(key, "must be true or false");
  return n->as_boolean()->get();
}

std::string TableReader::string(const std::string& key) {
  const toml::node* n = find(key);
  if (!n) fail(key, "missing; expected a string");
  if (!n->is_string()) fail(key, "must be a string");
  return n->as_string()->get();
}

std::string TableReader::string_or(const std::string& key, const std::string& fallback) {
  if (!has(key)) return fallback;
  return string(key);
}

std::vector<double> TableReader::numbers(const std::string& key, int count, double lo, double hi) {
  const toml::node* n = find(key);
  if (!n) fail(key, "missing; expected an array of numbers in " + range(lo, hi));
  const toml::array* a = n->as_array();
  if (!a) fail(key, "must be an array of numbers");
  if (count >= 0 && static_cast<int>(a->size()) != count)
    fail(key, "must have exactly " + std::to_string(count) + " entries, has " +
                  std::to_string(a->size()));
  std::vector<double> out;
  for (size_t i = 0; i < a->size(); ++i) {
    std::optional<double> v = (*a)[i].is_number() ? (*a)[i].value<double>() : std::nullopt;
    const std::string k = key + "[" + std::to_string(i) + "]";
    if (!v) fail(k, "must be a number");
    if (!std::isfinite(*v) || *v < lo || *v > hi)
      fail(k, "value " + fmt(*v) + " is out of range; allowed " + range(lo, hi));
    out.push_back(*v);
  }
  return out;
}

TableReader TableReader::table(const std::string& key) {
  const toml::node* n = find(key);
  if (!n) fail(key, "missing table");
  const toml::table* t = n->as_table();
  if (!t) fail(key, "must be a table");
  return TableReader(*t, key_path(key), *source_);
}

std::vector<TableReader> TableReader::tables(const std::string& key, int min_count, int max_count) {
  std::vector<TableReader> out;
  const toml::node* n = find(key);
  if (!n) {
    if (min_count > 0) fail(key, "missing; expected at least " + std::to_string(min_count) + " [[" + key_path(key) + "]] entries");
    return out;
  }
  const toml::array* a = n->as_array();
  if (!a) fail(key, "must be an array of tables ([[" + key_path(key) + "]])");
  const int sz = static_cast<int>(a->size());
  if (sz < min_count || sz > max_count)
    fail(key, "has " + std::to_string(sz) + " entries; allowed " + std::to_string(min_count) +
                  (min_count == max_count ? "" : " to " + std::to_string(max_count)));
  for (int i = 0; i < sz; ++i) {
    const toml::table* t = (*a)[static_cast<size_t>(i)].as_table();
    if (!t) fail(key + "[" + std::to_string(i) + "]", "must be a table");
    out.emplace_back(*t, key_path(key) + "[" + std::to_string(i) + "]", *source_);
  }
  return out;
}

std::vector<TableReader> TableReader::inline_tables(const std::string& key, int min_count,
                                                    int max_count) {
  return tables(key, min_count, max_count);
}

std::vector<std::pair<std::string, std::string>> TableReader::string_entries() {
  std::vector<std::pair<std::string, std::string>> out;
  for (auto&& [k, v] : *table_) {
    const std::string key(k.str());
    read_.insert(key);
    if (!v.is_string()) fail(key, "must be a string giving the reason");
    out.emplace_back(key, v.as_string()->get());
  }
  return out;
}

void TableReader::finish() {
  for (auto&& [k, v] : *table_) {
    const std::string key(k.str());
    if (!read_.count(key)) fail(key, "unknown key (not part of the board schema)");
  }
}

}  // namespace amb::board
