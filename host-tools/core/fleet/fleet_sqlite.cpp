// SQLite backend of the fleet store: one file, WAL journal (a reader never blocks the
// importer; a killed writer's transaction is rolled back at the next open), foreign keys on.
#include <sqlite3.h>

#include <string>

#include "host-tools/core/fleet/fleet_db.hpp"

namespace amb::host::fleet {
namespace {

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

std::string head(const std::string& sql) { return sql.substr(0, std::min<size_t>(sql.size(), 60)); }

class SqliteDb final : public Database {
 public:
  explicit SqliteDb(const std::string& path) : path_(path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr) != SQLITE_OK) {
      const std::string m = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw DbError("fleet store " + path + ": cannot open: " + m);
    }
    sqlite3_busy_timeout(db_, 30000);
    script("PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON;");
  }
  ~SqliteDb() override { sqlite3_close(db_); }

  std::vector<Row> query(const std::string& sql, const std::vector<Value>& params) override {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &st, nullptr) != SQLITE_OK) fail(sql);
    struct Finalize {
      sqlite3_stmt* s;
      ~Finalize() { sqlite3_finalize(s); }
    } fin{st};
    for (size_t i = 0; i < params.size(); ++i) {
      const int k = static_cast<int>(i + 1);
      const Value& v = params[i];
      int rc = SQLITE_OK;
      switch (v.index()) {
        case 0: rc = sqlite3_bind_null(st, k); break;
        case 1: rc = sqlite3_bind_int64(st, k, std::get<std::int64_t>(v)); break;
        case 2: rc = sqlite3_bind_double(st, k, std::get<double>(v)); break;
        case 3: {
          const auto& s = std::get<std::string>(v);
          rc = sqlite3_bind_text(st, k, s.data(), static_cast<int>(s.size()), SQLITE_TRANSIENT);
          break;
        }
        default: {
          const auto& b = std::get<Blob>(v).bytes;
          rc = sqlite3_bind_blob64(st, k, b.data(), b.size(), SQLITE_TRANSIENT);
        }
      }
      if (rc != SQLITE_OK) fail(sql);
    }
    std::vector<Row> rows;
    for (;;) {
      const int rc = sqlite3_step(st);
      if (rc == SQLITE_DONE) break;
      if (rc != SQLITE_ROW) fail(sql);
      Row r;
      const int n = sqlite3_column_count(st);
      for (int c = 0; c < n; ++c) {
        switch (sqlite3_column_type(st, c)) {
          case SQLITE_NULL: r.emplace_back(std::monostate{}); break;
          case SQLITE_INTEGER: r.emplace_back(static_cast<std::int64_t>(sqlite3_column_int64(st, c))); break;
          case SQLITE_FLOAT: r.emplace_back(sqlite3_column_double(st, c)); break;
          case SQLITE_TEXT:
            r.emplace_back(std::string(reinterpret_cast<const char*>(sqlite3_column_text(st, c)),
                                       static_cast<size_t>(sqlite3_column_bytes(st, c))));
            break;
          default: {
            const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(st, c));
            r.emplace_back(Blob{std::vector<std::uint8_t>(p, p + sqlite3_column_bytes(st, c))});
          }
        }
      }
      rows.push_back(std::move(r));
    }
    return rows;
  }

  void script(const std::string& sql) override {
    std::string s = replace_all(sql, "{id}", "INTEGER PRIMARY KEY");
    s = replace_all(s, "{blob}", "BLOB");
    char* err = nullptr;
    if (sqlite3_exec(db_, s.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
      const std::string m = err ? err : "error";
      sqlite3_free(err);
      throw DbError("fleet store " + path_ + ": " + head(sql) + "...: " + m);
    }
  }
  void begin() override { script("BEGIN IMMEDIATE"); }
  void commit() override { script("COMMIT"); }
  void rollback() override { script("ROLLBACK"); }
  std::string engine() const override { return "sqlite"; }

 private:
  [[noreturn]] void fail(const std::string& sql) { throw DbError("fleet store " + path_ + ": " + head(sql) + "...: " + sqlite3_errmsg(db_)); }
  sqlite3* db_ = nullptr;
  std::string path_;
};

}  // namespace

std::unique_ptr<Database> open_sqlite(const std::string& path) { return std::make_unique<SqliteDb>(path); }

}  // namespace amb::host::fleet
