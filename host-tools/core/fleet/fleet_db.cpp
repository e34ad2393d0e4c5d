#include "host-tools/core/fleet/fleet_db.hpp"

#include <cstdio>

namespace amb::host::fleet {

std::unique_ptr<Database> open_database(const std::string& url) {
  if (url.rfind("postgresql://", 0) == 0 || url.rfind("postgres://", 0) == 0) return open_postgres(url);
  if (url.rfind("postgres:", 0) == 0) return open_postgres(url.substr(9));
  if (url.rfind("sqlite:", 0) == 0) return open_sqlite(url.substr(7));
  return open_sqlite(url);
}

bool is_null(const Value& v) { return std::holds_alternative<std::monostate>(v); }

std::int64_t as_int(const Value& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  throw DbError("fleet store: expected an integer value");
}

double as_double(const Value& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  throw DbError("fleet store: expected a number");
}

std::string as_text(const Value& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  if (is_null(v)) return {};
  throw DbError("fleet store: expected text");
}

std::string canonical(const Value& v) {
  char b[40];
  switch (v.index()) {
    case 0: return "NULL";
    case 1: return std::to_string(std::get<std::int64_t>(v));
    case 2: std::snprintf(b, sizeof b, "%.17g", std::get<double>(v)); return b;
    case 3: return "'" + std::get<std::string>(v) + "'";
    default: return "blob(" + std::to_string(std::get<Blob>(v).bytes.size()) + ")";
  }
}

}  // namespace amb::host::fleet
