#include "host-tools/core/envelope/envelope_spec.hpp"
#include "firmware/board/board_text.hpp"
#include "host-tools/core/io/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <set>
#include <sstream>

#include <toml++/toml.h>

namespace amb::host::envelope {
namespace {

const char* const k_channel_names[4] = {"A1", "A2", "B1", "B2"};

/// Strict reader of one spec table: every key must be read (else "unknown key").
class Reader {
 public:
  Reader(const toml::table& t, std::string path, const std::string& source) : t_(t), path_(std::move(path)), source_(source) {}
  std::string key(const std::string& k) const { return path_ + "." + k; }
  [[noreturn]] void fail(const std::string& k, const std::string& m) const { throw SpecError(source_, key(k), m); }
  const toml::node* get(const std::string& k) {
    const toml::node* n = t_.get(k);
    if (n) read_.insert(k);
    return n;
  }
  double number_or(const std::string& k, double fallback, double lo, double hi) {
    const toml::node* n = get(k);
    if (!n) return fallback;
    return number_of(*n, k, lo, hi);
  }
  double number_of(const toml::node& n, const std::string& k, double lo, double hi) const {
    if (!n.is_number()) fail(k, "must be a number in [" + io::printf_text("%g", lo) + ", " + io::printf_text("%g", hi) + "]");
    const double v = *n.value<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(k, "value " + io::printf_text("%g", v) + " is out of range; allowed [" + io::printf_text("%g", lo) + ", " + io::printf_text("%g", hi) + "]");
    return v;
  }
  long long integer_or(const std::string& k, long long fallback, long long lo, long long hi) {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_integer()) fail(k, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    const long long v = n->as_integer()->get();
    if (v < lo || v > hi)
      fail(k, "value " + std::to_string(v) + " is out of range; allowed [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
  std::string string_or(const std::string& k, const std::string& fallback, const std::vector<std::string>& allowed = {}) {
    const toml::node* n = get(k);
    if (!n) return fallback;
    if (!n->is_string()) fail(k, "must be a string");
    std::string v = n->as_string()->get();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(k, "'" + v + "' is not one of " + list);
    }
    return v;
  }
  /// A numeric axis: number (fixed), array of numbers (levels) or {min, max, points}.
  NumericAxis axis_or(const std::string& k, double fallback, double lo, double hi) {
    NumericAxis a;
    const toml::node* n = get(k);
    if (!n) {
      a.levels = {fallback};
      return a;
    }
    if (n->is_number()) {
      a.levels = {number_of(*n, k, lo, hi)};
      return a;
    }
    if (const toml::array* arr = n->as_array()) {
      if (arr->empty()) fail(k, "an empty list; give at least one value");
      a.kind = NumericAxis::Kind::levels;
      for (size_t i = 0; i < arr->size(); ++i) a.levels.push_back(number_of(*arr->get(i), k + "[" + std::to_string(i) + "]", lo, hi));
      return a;
    }
    if (const toml::table* t = n->as_table()) {
      Reader r(*t, key(k), source_);
      a.kind = NumericAxis::Kind::range;
      if (!t->contains("min")) r.fail("min", "missing; a range needs min and max");
      if (!t->contains("max")) r.fail("max", "missing; a range needs min and max");
      a.min = r.number_or("min", 0.0, lo, hi);
      a.max = r.number_or("max", 0.0, lo, hi);
      if (!(a.max > a.min)) r.fail("max", "must be > min (" + io::printf_text("%g", a.min) + ")");
      a.points = static_cast<int>(r.integer_or("points", 2, 2, 10000));
      r.finish();
      return a;
    }
    fail(k, "must be a number, a list of numbers or a table {min, max, points}");
  }
  void finish() const {
    for (const auto& [k, v] : t_)
      if (!read_.count(std::string(k.str()))) fail(std::string(k.str()), "unknown key");
  }

 private:
  const toml::table& t_;
  std::string path_;
  const std::string& source_;
  std::set<std::string> read_;
};

double axis_max_abs(const NumericAxis& a) {
  if (a.kind == NumericAxis::Kind::range) return std::max(std::abs(a.min), std::abs(a.max));
  double m = 0.0;
  for (double v : a.levels) m = std::max(m, std::abs(v));
  return m;
}
double axis_min(const NumericAxis& a) {
  if (a.kind == NumericAxis::Kind::range) return a.min;
  return *std::min_element(a.levels.begin(), a.levels.end());
}

/// Grid values of an axis.
std::vector<double> grid_levels(const NumericAxis& a) {
  if (a.kind != NumericAxis::Kind::range) return a.levels;
  std::vector<double> v(static_cast<size_t>(a.points));
  for (int i = 0; i < a.points; ++i)
    v[static_cast<size_t>(i)] = a.min + (a.max - a.min) * static_cast<double>(i) / static_cast<double>(a.points - 1);
  return v;
}

/// splitmix64: a small portable generator (same sample on every platform and library).
struct SplitMix {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

/// One hypercube column: n stratified draws in [0, 1), strata in random order.
std::vector<double> lhs_column(SplitMix& rng, int n) {
  std::vector<int> perm(static_cast<size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  for (int i = n - 1; i > 0; --i) std::swap(perm[static_cast<size_t>(i)], perm[rng.next() % static_cast<std::uint64_t>(i + 1)]);
  std::vector<double> u(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) u[static_cast<size_t>(i)] = (perm[static_cast<size_t>(i)] + rng.uniform()) / n;
  return u;
}

/// Value of an axis at a stratified draw u in [0, 1).
double lhs_value(const NumericAxis& a, double u) {
  if (a.kind == NumericAxis::Kind::range) return a.min + u * (a.max - a.min);
  const size_t k = std::min(a.levels.size() - 1, static_cast<size_t>(u * static_cast<double>(a.levels.size())));
  return a.levels[k];
}

}  // namespace

SpecError::SpecError(const std::string& source, const std::string& key, const std::string& message)
    : std::runtime_error(source + ": " + key + ": " + message), key_(key) {}

std::uint8_t parse_channels(const std::string& text) {
  if (text == "all") return k_all_channels;
  std::uint8_t mask = 0;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, '+')) {
    int found = -1;
    for (int i = 0; i < 4; ++i)
      if (item == k_channel_names[i]) found = i;
    if (found < 0) throw std::invalid_argument("'" + item + "' is not a channel (A1, A2, B1, B2 joined by '+', or all)");
    mask = static_cast<std::uint8_t>(mask | (1u << found));
  }
  if (mask == 0) throw std::invalid_argument("no channel named (A1, A2, B1, B2 joined by '+', or all)");
  return mask;
}

std::string channels_name(std::uint8_t mask) {
  if ((mask & k_all_channels) == k_all_channels) return "all";
  std::string s;
  for (int i = 0; i < 4; ++i)
    if (mask & (1u << i)) s += (s.empty() ? "" : "+") + std::string(k_channel_names[i]);
  return s;
}

StudySpec parse_spec(const std::string& toml_text, const std::string& source) {
  toml::table root;
  std::string screened;  // toml++ 3.3 must not see non-ASCII outside comments (board_text.hpp)
  try {
    screened = amb::board::screen_toml_text(toml_text);
  } catch (const std::invalid_argument& e) {
    throw SpecError(source, "(syntax)", e.what());
  }
  try {
    root = toml::parse(screened, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << "line " << e.source().begin.line << ": " << e.description();
    throw SpecError(source, "(syntax)", os.str());
  }
  StudySpec s;
  s.source = source;
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key != "study" && key != "parameters") throw SpecError(source, key, "unknown table (allowed: study, parameters)");
    if (!v.is_table()) throw SpecError(source, key, "must be a table");
  }
  const toml::table* st = root["study"].as_table();
  if (!st) throw SpecError(source, "study", "missing table [study]");
  Reader r(*st, "study", source);
  s.settings.board = r.string_or("board", s.settings.board);
  s.method = r.string_or("method", s.method, {"grid", "lhs"});
  s.lhs_cases = static_cast<int>(r.integer_or("cases", 0, 1, 10'000'000));
  if (s.method == "lhs" && s.lhs_cases == 0) r.fail("cases", "missing; method = \"lhs\" needs the number of cases");
  if (s.method == "grid" && st->contains("cases")) r.fail("cases", "only for method = \"lhs\" (a grid's size follows from its parameters)");
  s.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1, 0, (1ll << 62)));
  s.worst_count = static_cast<int>(r.integer_or("worst", 10, 1, 1000));
  s.settings.settle_s = r.number_or("settle_s", s.settings.settle_s, 0.0, 10.0);
  s.settings.window_s = r.number_or("window_s", s.settings.window_s, 1e-3, 60.0);
  s.settings.sample_rate_hz = r.number_or("sample_rate_hz", s.settings.sample_rate_hz, 100.0, 1e6);
  s.settings.step_s = r.number_or("step_s", s.settings.step_s, 1e-7, 1e-3);
  if (s.settings.step_s > 1.0 / s.settings.sample_rate_hz) r.fail("step_s", "must not be longer than one record period (1 / sample_rate_hz)");
  s.settings.contact_law = r.string_or("contact_law", s.settings.contact_law, {"board", "rigid", "hertz", "linear"});
  s.settings.friction_energy_budget_j = r.number_or("friction_energy_budget_j", s.settings.friction_energy_budget_j, 1e-6, 1e12);
  r.finish();

  const toml::table* pt = root["parameters"].as_table();
  if (!pt) throw SpecError(source, "parameters", "missing table [parameters]");
  Reader p(*pt, "parameters", source);
  if (!pt->contains("speed_hz")) p.fail("speed_hz", "missing; the drive speed before the drop is required");
  s.speed_hz = p.axis_or("speed_hz", 0.0, 0.0, 5000.0);
  s.friction = p.axis_or("friction", 0.15, 0.0, 2.0);
  s.unbalance_factor = p.axis_or("unbalance_factor", 1.0, 0.0, 1000.0);
  s.clearance_m = p.axis_or("clearance_m", 0.0, 0.0, 0.01);
  s.offset_x_m = p.axis_or("offset_x_m", 0.0, -0.01, 0.01);
  s.offset_y_m = p.axis_or("offset_y_m", 0.0, -0.01, 0.01);
  if (const toml::node* n = p.get("failed_channels")) {
    s.failed_channels.clear();
    auto one = [&](const toml::node& e, const std::string& k) {
      if (!e.is_string()) p.fail(k, "must be a string: \"all\" or channels joined by '+' (e.g. \"A1+B2\")");
      try {
        s.failed_channels.push_back(parse_channels(e.as_string()->get()));
      } catch (const std::invalid_argument& ex) {
        p.fail(k, ex.what());
      }
    };
    if (const toml::array* arr = n->as_array()) {
      if (arr->empty()) p.fail("failed_channels", "an empty list; give at least one set");
      for (size_t i = 0; i < arr->size(); ++i) one(*arr->get(i), "failed_channels[" + std::to_string(i) + "]");
    } else {
      one(*n, "failed_channels");
    }
  }
  p.finish();
  // Clearance 0 means "the board's"; a given clearance must exceed every centre offset.
  if (pt->contains("clearance_m") && !(axis_min(s.clearance_m) > 0.0)) p.fail("clearance_m", "must be > 0 m");
  const double off = std::hypot(axis_max_abs(s.offset_x_m), axis_max_abs(s.offset_y_m));
  if (pt->contains("clearance_m") && off >= axis_min(s.clearance_m))
    p.fail("offset_x_m", "centre offsets up to " + io::printf_text("%g", off) + " m reach the smallest clearance " + io::printf_text("%g", axis_min(s.clearance_m)) + " m");
  if (s.method == "grid") {
    double n = 1.0;
    for (const NumericAxis* a : {&s.speed_hz, &s.friction, &s.unbalance_factor, &s.clearance_m, &s.offset_x_m, &s.offset_y_m})
      n *= static_cast<double>(grid_levels(*a).size());
    n *= static_cast<double>(s.failed_channels.size());
    if (n > 1e7) throw SpecError(source, "parameters", "the grid has " + io::printf_text("%g", n) + " cases (at most 1e7)");
  }
  return s;
}

StudySpec load_spec(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw SpecError(path, "(file)", "cannot be read");
  std::ostringstream os;
  os << f.rdbuf();
  return parse_spec(os.str(), path);
}

std::vector<CaseParams> expand_cases(const StudySpec& s) {
  std::vector<CaseParams> out;
  if (s.method == "grid") {
    const auto sp = grid_levels(s.speed_hz), mu = grid_levels(s.friction), ub = grid_levels(s.unbalance_factor),
               cl = grid_levels(s.clearance_m), ox = grid_levels(s.offset_x_m), oy = grid_levels(s.offset_y_m);
    for (double a : sp)
      for (double b : mu)
        for (double c : ub)
          for (double d : cl)
            for (double e : ox)
              for (double f : oy)
                for (std::uint8_t ch : s.failed_channels) out.push_back({a, b, c, d, e, f, ch});
    return out;
  }
  const int n = s.lhs_cases;
  SplitMix rng{s.seed};
  std::vector<std::vector<double>> cols;
  for (int k = 0; k < 7; ++k) cols.push_back(lhs_column(rng, n));
  out.resize(static_cast<size_t>(n));
  for (size_t i = 0; i < out.size(); ++i) {
    CaseParams& c = out[i];
    c.speed_hz = lhs_value(s.speed_hz, cols[0][i]);
    c.friction = lhs_value(s.friction, cols[1][i]);
    c.unbalance_factor = lhs_value(s.unbalance_factor, cols[2][i]);
    c.clearance_m = lhs_value(s.clearance_m, cols[3][i]);
    c.offset_x_m = lhs_value(s.offset_x_m, cols[4][i]);
    c.offset_y_m = lhs_value(s.offset_y_m, cols[5][i]);
    const size_t k = std::min(s.failed_channels.size() - 1, static_cast<size_t>(cols[6][i] * static_cast<double>(s.failed_channels.size())));
    c.failed_channels = s.failed_channels[k];
  }
  return out;
}

std::vector<std::string> varying_parameters(const StudySpec& s) {
  std::vector<std::string> v;
  const std::pair<const char*, const NumericAxis*> axes[] = {{"speed_hz", &s.speed_hz},       {"friction", &s.friction},
                                                            {"unbalance_factor", &s.unbalance_factor},
                                                            {"clearance_m", &s.clearance_m}, {"offset_x_m", &s.offset_x_m},
                                                            {"offset_y_m", &s.offset_y_m}};
  for (const auto& [name, a] : axes)
    if (a->varies()) v.push_back(name);
  if (s.failed_channels.size() > 1) v.push_back("failed_channels");
  return v;
}

double parameter_value(const CaseParams& c, const std::string& name) {
  if (name == "speed_hz") return c.speed_hz;
  if (name == "friction") return c.friction;
  if (name == "unbalance_factor") return c.unbalance_factor;
  if (name == "clearance_m") return c.clearance_m;
  if (name == "offset_x_m") return c.offset_x_m;
  if (name == "offset_y_m") return c.offset_y_m;
  if (name == "failed_channels") return c.failed_channels;
  throw std::invalid_argument("no case parameter '" + name + "'");
}

}  // namespace amb::host::envelope
