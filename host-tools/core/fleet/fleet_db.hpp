#pragma once
// The fleet store's database connection: one small interface, two backends — SQLite (one
// file, no server; the default) and PostgreSQL (libpq; a shared server). SQL is written once
// with '?' placeholders and the types both engines share (BIGINT, DOUBLE PRECISION, TEXT);
// the few DDL words that differ are tokens the backend replaces ({id}: auto-numbered
// primary key, {blob}: byte string). Values come back typed (Value), so the same query gives
// the same rows on both engines.
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace amb::host::fleet {

/// One SQL value: NULL, integer, double, text or bytes.
struct Blob {
  std::vector<std::uint8_t> bytes;
};
using Value = std::variant<std::monostate, std::int64_t, double, std::string, Blob>;
using Row = std::vector<Value>;

/// A database error; what() names the statement's first words and the engine's message.
class DbError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Database {
 public:
  virtual ~Database() = default;
  /// Run a statement with bound parameters; rows it returns (empty for none).
  virtual std::vector<Row> query(const std::string& sql, const std::vector<Value>& params = {}) = 0;
  /// Run a script of statements without parameters (DDL; tokens replaced).
  virtual void script(const std::string& sql) = 0;
  virtual void begin() = 0;
  virtual void commit() = 0;
  virtual void rollback() = 0;
  /// "sqlite" or "postgresql".
  virtual std::string engine() const = 0;
};

/// Open a store: "postgresql://..." or "postgres:CONNINFO" (libpq conninfo) for PostgreSQL,
/// else "sqlite:PATH" or a plain PATH for SQLite (the file is created). Throws DbError.
std::unique_ptr<Database> open_database(const std::string& url);

/// Rolls back unless commit() was called (exceptions leave the store unchanged).
class Transaction {
 public:
  explicit Transaction(Database& db) : db_(db) { db_.begin(); }
  ~Transaction() {
    if (!done_) try {
        db_.rollback();
      } catch (...) {
      }
  }
  void commit() {
    db_.commit();
    done_ = true;
  }

 private:
  Database& db_;
  bool done_ = false;
};

/// Value helpers (throw DbError on a type mismatch).
std::int64_t as_int(const Value& v);
double as_double(const Value& v);  ///< integers convert
std::string as_text(const Value& v);
bool is_null(const Value& v);
/// Canonical text of a value for comparisons across engines (doubles with %.17g).
std::string canonical(const Value& v);

// Backends (fleet_sqlite.cpp, fleet_postgres.cpp).
std::unique_ptr<Database> open_sqlite(const std::string& path);
std::unique_ptr<Database> open_postgres(const std::string& conninfo);

}  // namespace amb::host::fleet
