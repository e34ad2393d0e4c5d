#include "host-tools/core/tracking/machine_profile.hpp"
#include "firmware/board/board_text.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <toml++/toml.h>

namespace amb::host {
namespace {

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  throw std::invalid_argument(source + ": " + key + ": " + what);
}

void only_keys(const toml::table& t, const std::set<std::string>& allowed, const std::string& source,
               const std::string& prefix) {
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    if (!allowed.count(key)) fail(source, prefix + key, "unknown key");
  }
}

double number(const toml::table& t, const std::string& key, const std::string& path, double fallback, double lo,
              double hi, bool lo_open, const std::string& source) {
  const toml::node* n = t.get(key);
  if (!n) return fallback;
  std::optional<double> v = n->value<double>();
  if (!v || !(n->is_integer() || n->is_floating_point())) fail(source, path, "must be a number");
  if (!std::isfinite(*v) || *v > hi || *v < lo || (lo_open && *v == lo))
    fail(source, path, "must be in " + std::string(lo_open ? "(" : "[") + std::to_string(lo) + ", " +
                           std::to_string(hi) + "], got " + std::to_string(*v));
  return *v;
}

}  // namespace

MachineProfile default_machine_profile() { return MachineProfile{}; }

MachineProfile parse_machine_profile(std::string_view toml_text, const std::string& source) {
  toml::table root;
  std::string screened;  // toml++ 3.3 must not see non-ASCII outside comments (board_text.hpp)
  try {
    screened = amb::board::screen_toml_text(toml_text);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
  try {
    root = toml::parse(screened, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << source << ": TOML syntax error at line " << e.source().begin.line << ": " << e.description();
    throw std::invalid_argument(os.str());
  }
  MachineProfile p;
  p.from_file = true;
  only_keys(root, {"schema", "name", "speed", "orders"}, source, "");
  const auto schema = root["schema"].value<std::string>();
  if (!schema) fail(source, "schema", "missing (expected \"amb-machine/1\")");
  if (*schema != "amb-machine/1") fail(source, "schema", "must be \"amb-machine/1\", got \"" + *schema + "\"");
  if (const toml::node* n = root.get("name")) {
    if (!n->is_string()) fail(source, "name", "must be a string");
    p.name = *n->value<std::string>();
  }
  const toml::table* speed = root["speed"].as_table();
  if (!speed) fail(source, "speed", "missing table [speed] (min_hz, max_hz, max_accel_hz_per_s)");
  only_keys(*speed, {"min_hz", "max_hz", "max_accel_hz_per_s"}, source, "speed.");
  if (!speed->get("min_hz")) fail(source, "speed.min_hz", "missing");
  if (!speed->get("max_hz")) fail(source, "speed.max_hz", "missing");
  p.min_speed_hz = number(*speed, "min_hz", "speed.min_hz", p.min_speed_hz, 0.1, 5000.0, false, source);
  p.max_speed_hz = number(*speed, "max_hz", "speed.max_hz", p.max_speed_hz, 0.1, 5000.0, false, source);
  if (!(p.max_speed_hz > p.min_speed_hz))
    fail(source, "speed.max_hz", "must be above speed.min_hz (" + std::to_string(p.min_speed_hz) + ")");
  p.max_accel_hz_per_s =
      number(*speed, "max_accel_hz_per_s", "speed.max_accel_hz_per_s", p.max_accel_hz_per_s, 0.0, 1e5, true, source);
  if (const toml::table* orders = root["orders"].as_table()) {
    only_keys(*orders, {"comb"}, source, "orders.");
    const toml::node* c = orders->get("comb");
    if (!c) fail(source, "orders.comb", "missing (\"discover\" or an array of orders)");
    if (c->is_string()) {
      if (*c->value<std::string>() != "discover")
        fail(source, "orders.comb", "string must be \"discover\", got \"" + *c->value<std::string>() + "\"");
      p.discover_orders = true;
    } else if (const toml::array* a = c->as_array()) {
      if (a->empty() || a->size() > 8) fail(source, "orders.comb", "needs 1 to 8 orders, got " + std::to_string(a->size()));
      p.discover_orders = false;
      for (size_t i = 0; i < a->size(); ++i) {
        const auto v = (*a)[i].value<double>();
        if (!v || !(*v > 0.0 && *v <= 100.0))
          fail(source, "orders.comb[" + std::to_string(i) + "]", "must be a number in (0, 100]");
        p.orders.push_back(*v);
      }
    } else {
      fail(source, "orders.comb", "must be \"discover\" or an array of numbers");
    }
  }
  return p;
}

MachineProfile load_machine_profile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot read the machine profile");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_machine_profile(ss.str(), path);
}

}  // namespace amb::host
