// PostgreSQL backend of the fleet store (libpq from Debian). Parameters are sent as text
// (bytes as binary), results read as text and typed by the column's type OID, so values come
// back as the same Value kinds as from SQLite.
#include <libpq-fe.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <string>

#include "host-tools/core/fleet/fleet_db.hpp"

namespace amb::host::fleet {
namespace {

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

/// '?' placeholders -> $1, $2, ... (the store's SQL has no '?' inside literals).
std::string numbered(const std::string& sql) {
  std::string out;
  int n = 0;
  for (char c : sql) {
    if (c == '?') out += "$" + std::to_string(++n);
    else out += c;
  }
  return out;
}

std::string head(const std::string& sql) { return sql.substr(0, std::min<size_t>(sql.size(), 60)); }

int hex(char c) { return c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10; }

class PostgresDb final : public Database {
 public:
  explicit PostgresDb(const std::string& conninfo) {
    conn_ = PQconnectdb(conninfo.c_str());
    if (PQstatus(conn_) != CONNECTION_OK) {
      const std::string m = PQerrorMessage(conn_);
      PQfinish(conn_);
      throw DbError("fleet store (postgresql): cannot connect: " + m);
    }
    script("SET client_min_messages = warning");
  }
  ~PostgresDb() override { PQfinish(conn_); }

  std::vector<Row> query(const std::string& sql, const std::vector<Value>& params) override {
    std::vector<std::string> text(params.size());
    std::vector<const char*> values(params.size(), nullptr);
    std::vector<int> lengths(params.size(), 0), formats(params.size(), 0);
    for (size_t i = 0; i < params.size(); ++i) {
      const Value& v = params[i];
      char b[40];
      switch (v.index()) {
        case 0: continue;
        case 1: text[i] = std::to_string(std::get<std::int64_t>(v)); break;
        case 2: std::snprintf(b, sizeof b, "%.17g", std::get<double>(v)); text[i] = b; break;
        case 3: text[i] = std::get<std::string>(v); break;
        default: {
          const auto& by = std::get<Blob>(v).bytes;
          text[i].assign(by.begin(), by.end());
          formats[i] = 1;
        }
      }
      values[i] = text[i].data();
      lengths[i] = static_cast<int>(text[i].size());
    }
    PGresult* res = PQexecParams(conn_, numbered(sql).c_str(), static_cast<int>(params.size()), nullptr, values.data(),
                                 lengths.data(), formats.data(), 0);
    struct Clear {
      PGresult* r;
      ~Clear() { PQclear(r); }
    } clear{res};
    const ExecStatusType st = PQresultStatus(res);
    if (st != PGRES_TUPLES_OK && st != PGRES_COMMAND_OK) throw DbError("fleet store (postgresql): " + head(sql) + "...: " + PQresultErrorMessage(res));
    std::vector<Row> rows;
    const int nr = PQntuples(res), nc = PQnfields(res);
    for (int r = 0; r < nr; ++r) {
      Row row;
      for (int c = 0; c < nc; ++c) {
        if (PQgetisnull(res, r, c)) {
          row.emplace_back(std::monostate{});
          continue;
        }
        const char* s = PQgetvalue(res, r, c);
        switch (PQftype(res, c)) {
          case 20: case 21: case 23: row.emplace_back(static_cast<std::int64_t>(std::strtoll(s, nullptr, 10))); break;
          case 16: row.emplace_back(static_cast<std::int64_t>(s[0] == 't')); break;
          case 700: case 701: case 1700: row.emplace_back(std::strtod(s, nullptr)); break;
          case 17: {  // bytea, hex output "\x0a1b..."
            Blob b;
            const size_t n = std::strlen(s);
            for (size_t k = 2; k + 1 < n; k += 2) b.bytes.push_back(static_cast<std::uint8_t>(hex(s[k]) * 16 + hex(s[k + 1])));
            row.emplace_back(std::move(b));
            break;
          }
          default: row.emplace_back(std::string(s, static_cast<size_t>(PQgetlength(res, r, c))));
        }
      }
      rows.push_back(std::move(row));
    }
    return rows;
  }

  void script(const std::string& sql) override {
    std::string s = replace_all(sql, "{id}", "BIGSERIAL PRIMARY KEY");
    s = replace_all(s, "{blob}", "BYTEA");
    PGresult* res = PQexec(conn_, s.c_str());
    const ExecStatusType st = PQresultStatus(res);
    const std::string m = PQresultErrorMessage(res);
    PQclear(res);
    if (st != PGRES_COMMAND_OK && st != PGRES_TUPLES_OK) throw DbError("fleet store (postgresql): " + head(sql) + "...: " + m);
  }
  void begin() override { script("BEGIN"); }
  void commit() override { script("COMMIT"); }
  void rollback() override { script("ROLLBACK"); }
  std::string engine() const override { return "postgresql"; }

 private:
  PGconn* conn_ = nullptr;
};

}  // namespace

std::unique_ptr<Database> open_postgres(const std::string& conninfo) { return std::make_unique<PostgresDb>(conninfo); }

}  // namespace amb::host::fleet
