#include "host-tools/core/events/measured_event.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

namespace amb::host {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) { throw EventLoadError(file + ": " + what); }

/// Scale to SI of a unit allowed for a quantity; false if not allowed.
bool unit_scale(const std::string& quantity, const std::string& unit, double& scale) {
  static const std::map<std::string, std::map<std::string, double>> units = {
      {"time", {{"s", 1.0}}},
      {"displacement", {{"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}}},
      {"current", {{"A", 1.0}}},
      {"speed", {{"Hz", 1.0}, {"rpm", 1.0 / 60.0}}},
      {"acceleration", {{"m/s^2", 1.0}, {"g", 9.80665}}},
      {"voltage", {{"V", 1.0}}},
  };
  const auto q = units.find(quantity);
  if (q == units.end()) return false;
  const auto u = q->second.find(unit);
  if (u == q->second.end()) return false;
  scale = u->second;
  return true;
}

std::string allowed_units(const std::string& quantity) {
  if (quantity == "time") return "s";
  if (quantity == "displacement") return "m, mm, um";
  if (quantity == "current") return "A";
  if (quantity == "speed") return "Hz, rpm";
  if (quantity == "acceleration") return "m/s^2, g";
  return "V";
}

bool positioned(const std::string& q) { return q == "displacement" || q == "current" || q == "acceleration"; }

double angle_diff_deg(double a, double b) { return std::abs(std::remainder(a - b, 360.0)); }

struct ChannelSpec {
  std::string column, quantity, unit;
  double scale = 1.0;
  double axial_m = 0.0, angle_deg = 0.0;
};

// `where`: the JSON path of the containing object ("" or "channels[3]."); messages name the
// field as 'channels[3].unit'.
double number_field(const json& j, const std::string& key, const std::string& where, const std::string& file) {
  const std::string f = "field '" + where + key + "'";
  if (!j.contains(key)) fail(file, f + " is missing; expected a number");
  const json& v = j.at(key);
  if (!v.is_number()) fail(file, f + " must be a number, got " + std::string(v.type_name()));
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(file, f + " must be finite");
  return d;
}

std::string string_field(const json& j, const std::string& key, const std::string& where, const std::string& file) {
  const std::string f = "field '" + where + key + "'";
  if (!j.contains(key)) fail(file, f + " is missing; expected a string");
  const json& v = j.at(key);
  if (!v.is_string()) fail(file, f + " must be a string, got " + std::string(v.type_name()));
  return v.get<std::string>();
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(c);
    }
  }
  out.push_back(cur);
  for (auto& s : out) {
    const auto a = s.find_first_not_of(" \t");
    const auto b = s.find_last_not_of(" \t");
    s = a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
  }
  return out;
}

bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e && std::isfinite(v);
}

}  // namespace

MeasuredEventPaths measured_event_paths(const std::string& path) {
  fs::path p(path);
  if (p.extension() == ".json" || p.extension() == ".csv") p.replace_extension();
  return {p.string() + ".json", p.string() + ".csv"};
}

board::BoardConfig resolve_rig(const std::string& rig, const std::string& dir, const std::string& file) {
  // A board named like the rig first (several boards may describe one rig, e.g. a HIL board).
  std::string known;
  for (const std::string& name : board::embedded_board_names())
    if (name == rig) return board::load_board(name);
  for (const std::string& name : board::embedded_board_names()) {
    board::BoardConfig b = board::load_board(name);
    if (b.plant.rig_name == rig) return b;
    known += (known.empty() ? "" : ", ") + b.plant.rig_name;
  }
  for (const fs::path& p : {fs::path(rig), fs::path(dir) / rig}) {
    std::error_code ec;
    if (!rig.empty() && fs::is_regular_file(p, ec)) {
      try {
        return board::load_board(p.string());
      } catch (const board::BoardError& e) {
        fail(file, std::string("field 'rig': board file is refused: ") + e.what());
      }
    }
  }
  fail(file, "field 'rig': '" + rig + "' is neither a rig of a board in boards/ (known: " + known +
                 ") nor a board file");
}

LoadedEvent read_measured_event(const std::string& path) {
  const MeasuredEventPaths paths = measured_event_paths(path);
  const std::string& jf = paths.json;
  json j;
  {
    std::ifstream in(jf);
    if (!in) fail(jf, "cannot open the sidecar");
    try {
      j = json::parse(in);
    } catch (const json::parse_error& e) {
      fail(jf, std::string("not valid JSON: ") + e.what());
    }
  }
  if (!j.is_object()) fail(jf, "the sidecar must be a JSON object");
  static const std::set<std::string> top_keys = {"format", "rig", "sample_rate_hz", "trigger_index",
                                                 "speed_rpm", "channels", "declared_faults", "notes"};
  for (const auto& [k, v] : j.items())
    if (!top_keys.count(k))
      fail(jf, "unknown field '" + k + "' (allowed: format, rig, sample_rate_hz, trigger_index, speed_rpm, channels, "
                                       "declared_faults, notes)");
  const std::string format = string_field(j, "format", "", jf);
  if (format != k_measured_event_format)
    fail(jf, "field 'format': expected \"" + std::string(k_measured_event_format) + "\", got \"" + format + "\"");
  const std::string rig = string_field(j, "rig", "", jf);
  const double fs_hz = number_field(j, "sample_rate_hz", "", jf);
  if (!(fs_hz > 0.0)) fail(jf, "field 'sample_rate_hz' must be > 0, got " + std::to_string(fs_hz));
  if (!j.contains("trigger_index")) fail(jf, "field 'trigger_index' is missing; expected an integer >= 0");
  if (!j["trigger_index"].is_number_integer() || j["trigger_index"].get<long long>() < 0)
    fail(jf, "field 'trigger_index' must be an integer >= 0");
  const auto trigger = static_cast<size_t>(j["trigger_index"].get<long long>());
  std::optional<double> speed_rpm;
  if (j.contains("speed_rpm")) {
    speed_rpm = number_field(j, "speed_rpm", "", jf);
    if (*speed_rpm < 0.0) fail(jf, "field 'speed_rpm' must be >= 0");
  }
  std::vector<std::string> declared;
  if (j.contains("declared_faults")) {
    if (!j["declared_faults"].is_array()) fail(jf, "field 'declared_faults' must be an array of strings");
    for (size_t i = 0; i < j["declared_faults"].size(); ++i) {
      if (!j["declared_faults"][i].is_string())
        fail(jf, "field 'declared_faults[" + std::to_string(i) + "]' must be a string");
      declared.push_back(j["declared_faults"][i].get<std::string>());
    }
  }
  std::string notes;
  if (j.contains("notes")) notes = string_field(j, "notes", "", jf);

  // Channels.
  if (!j.contains("channels") || !j["channels"].is_array() || j["channels"].empty())
    fail(jf, "field 'channels' must be a non-empty array of channel objects");
  std::vector<ChannelSpec> specs;
  std::set<std::string> columns;
  int n_time = 0, n_speed = 0;
  for (size_t i = 0; i < j["channels"].size(); ++i) {
    const json& c = j["channels"][i];
    const std::string where = "channels[" + std::to_string(i) + "].";
    if (!c.is_object()) fail(jf, "field 'channels[" + std::to_string(i) + "]' must be an object");
    static const std::set<std::string> ch_keys = {"column", "quantity", "unit", "axial_m", "angle_deg"};
    for (const auto& [k, v] : c.items())
      if (!ch_keys.count(k)) fail(jf, "field '" + where + k + "' is unknown (allowed: column, quantity, unit, axial_m, angle_deg)");
    ChannelSpec s;
    s.column = string_field(c, "column", where, jf);
    if (s.column.empty()) fail(jf, "field '" + where + "column' must not be empty");
    if (!columns.insert(s.column).second) fail(jf, "field '" + where + "column': '" + s.column + "' is named twice");
    s.quantity = string_field(c, "quantity", where, jf);
    static const std::set<std::string> quantities = {"time", "displacement", "current", "speed", "acceleration", "voltage"};
    if (!quantities.count(s.quantity))
      fail(jf, "field '" + where + "quantity': '" + s.quantity +
                   "' is not one of time, displacement, current, speed, acceleration, voltage");
    s.unit = string_field(c, "unit", where, jf);
    if (!unit_scale(s.quantity, s.unit, s.scale))
      fail(jf, "field '" + where + "unit': '" + s.unit + "' is not a unit of " + s.quantity + " (allowed: " +
                   allowed_units(s.quantity) + ")");
    if (positioned(s.quantity)) {
      s.axial_m = number_field(c, "axial_m", where, jf);
      s.angle_deg = number_field(c, "angle_deg", where, jf);
      if (s.axial_m < 0.0) fail(jf, "field '" + where + "axial_m' must be >= 0 m");
    } else if (c.contains("axial_m") || c.contains("angle_deg")) {
      fail(jf, "field '" + where + "': a " + s.quantity + " channel has no axial_m/angle_deg");
    }
    n_time += s.quantity == "time";
    n_speed += s.quantity == "speed";
    specs.push_back(s);
  }
  if (n_time > 1) fail(jf, "field 'channels': more than one time channel");
  if (n_speed > 1) fail(jf, "field 'channels': more than one speed channel");

  // The rig, for the channel match.
  const board::BoardConfig board = resolve_rig(rig, fs::path(jf).parent_path().string(), jf);

  // CSV.
  const std::string& cf = paths.csv;
  std::ifstream in(cf);
  if (!in) fail(cf, "cannot open the CSV file");
  std::string line;
  if (!std::getline(in, line)) fail(cf, "line 1: empty file, expected a header row");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string> header = split_csv(line);
  std::map<std::string, size_t> col_index;
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i].empty()) continue;
    if (!col_index.emplace(header[i], i).second && columns.count(header[i]))
      fail(cf, "line 1: column '" + header[i] + "' appears twice in the header");
  }
  std::vector<size_t> idx;
  for (const auto& s : specs) {
    const auto it = col_index.find(s.column);
    if (it == col_index.end()) fail(cf, "line 1: column '" + s.column + "' named in the sidecar is not in the header");
    idx.push_back(it->second);
  }
  std::vector<std::vector<double>> data(specs.size());
  size_t line_no = 1;
  bool blank_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) {
      blank_seen = true;
      continue;
    }
    if (blank_seen) fail(cf, "line " + std::to_string(line_no) + ": data after an empty line");
    const std::vector<std::string> f = split_csv(line);
    if (f.size() != header.size())
      fail(cf, "line " + std::to_string(line_no) + ": " + std::to_string(f.size()) + " fields, the header has " +
                   std::to_string(header.size()));
    for (size_t k = 0; k < specs.size(); ++k) {
      double v = 0.0;
      if (!parse_number(f[idx[k]], v))
        fail(cf, "line " + std::to_string(line_no) + ", column '" + specs[k].column + "': '" + f[idx[k]] +
                     "' is not a finite number");
      data[k].push_back(v * specs[k].scale);
    }
  }
  const size_t rows = data.front().size();
  if (rows < 2) fail(cf, "needs at least 2 data rows, has " + std::to_string(rows));
  if (trigger >= rows)
    fail(jf, "field 'trigger_index': " + std::to_string(trigger) + " is beyond the " + std::to_string(rows) +
                 " data rows of " + cf);

  LoadedEvent e;
  e.source = jf;
  e.format = k_measured_event_format;
  e.rig = rig;
  e.board = board.name;
  e.sample_rate_hz = fs_hz;
  e.trigger_index = trigger;
  e.declared_faults = declared;
  e.notes = notes;
  if (speed_rpm) e.speed_at_trigger_hz = *speed_rpm / 60.0;
  const double dt = 1.0 / fs_hz;
  e.t_s.resize(rows);
  for (size_t i = 0; i < rows; ++i) e.t_s[i] = static_cast<double>(i) * dt;
  const double tol_axial = board.capture.match_axial_tolerance_m;
  const double tol_angle = board.capture.match_angle_tolerance_deg;
  for (size_t k = 0; k < specs.size(); ++k) {
    const ChannelSpec& s = specs[k];
    if (s.quantity == "time") {
      // Uniform sampling at sample_rate_hz: every step within 1 % of 1/fs.
      for (size_t i = 1; i < rows; ++i) {
        const double step = data[k][i] - data[k][i - 1];
        if (std::abs(step - dt) > 0.01 * dt)
          fail(cf, "line " + std::to_string(i + 2) + ", column '" + s.column + "': time step " + std::to_string(step) +
                       " s does not match sample_rate_hz (expected " + std::to_string(dt) + " s)");
      }
      for (size_t i = 0; i < rows; ++i) e.t_s[i] = data[k][i] - data[k][0];
      continue;
    }
    if (s.quantity == "speed") {
      e.speed_hz = data[k];
      if (!e.speed_at_trigger_hz) e.speed_at_trigger_hz = data[k][trigger];
      continue;
    }
    LoadedChannel ch{s.column, s.quantity, s.axial_m, s.angle_deg, -1, false, std::move(data[k])};
    // Match to the rig: sensors for displacement, actuator axes for current.
    if (s.quantity == "displacement" || s.quantity == "current") {
      for (int r = 0; r < 4; ++r) {
        const double ax = s.quantity == "displacement" ? board.plant.sensor[static_cast<size_t>(r)].axial_m
                                                       : board.plant.amb[static_cast<size_t>(r / 2)].axial_m;
        const double an = s.quantity == "displacement"
                              ? board.plant.sensor[static_cast<size_t>(r)].angle_deg
                              : board.plant.amb[static_cast<size_t>(r / 2)].actuator_angle_deg[static_cast<size_t>(r % 2)];
        if (std::abs(ax - s.axial_m) > tol_axial) continue;
        if (angle_diff_deg(an, s.angle_deg) <= tol_angle) {
          ch.rig_index = r;
        } else if (angle_diff_deg(an + 180.0, s.angle_deg) <= tol_angle) {
          ch.rig_index = r;
          ch.inverted = true;
          for (double& v : ch.values) v = -v;
        }
        if (ch.rig_index >= 0) break;
      }
    }
    if (ch.rig_index < 0) {
      char b[256];
      std::snprintf(b, sizeof b, "channel '%s' (%s at %.4f m, %.1f deg) matches nothing on rig %s within %.4f m / %.1f deg",
                    s.column.c_str(), s.quantity.c_str(), s.axial_m, s.angle_deg, board.plant.rig_name.c_str(),
                    tol_axial, tol_angle);
      e.warnings.push_back(b);
    }
    if (s.quantity == "displacement") e.displacement.push_back(std::move(ch));
    else if (s.quantity == "current") e.current.push_back(std::move(ch));
    else e.other.push_back(std::move(ch));
  }
  return e;
}

namespace {
void write_file_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(path + ": write failed");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(path + ": rename failed: " + ec.message());
}
}  // namespace

void write_measured_event(const std::string& stem, const MeasuredEventOut& e) {
  const MeasuredEventPaths paths = measured_event_paths(stem);
  size_t rows = 0;
  for (const auto& c : e.columns) rows = std::max(rows, c.values ? c.values->size() : 0);
  for (const auto& c : e.columns)
    if (!c.values || c.values->size() != rows) throw std::runtime_error("column " + c.column + " has the wrong length");
  std::string csv;
  csv.reserve(rows * e.columns.size() * 16);
  for (size_t k = 0; k < e.columns.size(); ++k) csv += (k ? "," : "") + e.columns[k].column;
  csv += '\n';
  char b[40];
  for (size_t i = 0; i < rows; ++i) {
    for (size_t k = 0; k < e.columns.size(); ++k) {
      std::snprintf(b, sizeof b, "%s%.9g", k ? "," : "", (*e.columns[k].values)[i]);
      csv += b;
    }
    csv += '\n';
  }
  json j;
  j["format"] = k_measured_event_format;
  j["rig"] = e.rig;
  j["sample_rate_hz"] = e.sample_rate_hz;
  j["trigger_index"] = e.trigger_index;
  if (e.speed_rpm) j["speed_rpm"] = *e.speed_rpm;
  j["channels"] = json::array();
  for (const auto& c : e.columns) {
    if (!c.in_sidecar) continue;
    json ch = {{"column", c.column}, {"quantity", c.quantity}, {"unit", c.unit}};
    if (c.positioned) {
      ch["axial_m"] = c.axial_m;
      ch["angle_deg"] = c.angle_deg;
    }
    j["channels"].push_back(ch);
  }
  j["declared_faults"] = e.declared_faults;
  j["notes"] = e.notes;
  // CSV first: a sidecar never points at a missing or partial CSV.
  write_file_atomic(paths.csv, csv);
  write_file_atomic(paths.json, j.dump(2) + "\n");
}

void export_measured_event(const LoadedEvent& e, const std::string& stem) {
  MeasuredEventOut out;
  out.rig = e.rig;
  out.sample_rate_hz = e.sample_rate_hz;
  out.trigger_index = e.trigger_index;
  if (e.speed_at_trigger_hz && std::isfinite(*e.speed_at_trigger_hz)) out.speed_rpm = *e.speed_at_trigger_hz * 60.0;
  out.declared_faults = e.declared_faults;
  out.notes = e.notes;
  if (e.phase_b)
    out.notes += (out.notes.empty() ? "" : "; ") + std::string("board Phase B: ") + fw::diag::to_string(e.phase_b->type) +
                 " (confidence " + std::to_string(e.phase_b->confidence) + "): " + e.phase_b->summary;
  // The exchange format is uniformly sampled: nominal time i/fs; the board's clock goes in an
  // extra column.
  std::vector<double> t(e.samples());
  for (size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) / e.sample_rate_hz;
  out.columns.push_back({"t_s", "time", "s", false, 0, 0, &t, true});
  for (const auto& c : e.displacement) out.columns.push_back({"x_" + c.name, "displacement", "m", true, c.axial_m, c.angle_deg, &c.values, true});
  for (const auto& c : e.current) out.columns.push_back({"i_" + c.name, "current", "A", true, c.axial_m, c.angle_deg, &c.values, true});
  for (const auto& c : e.other)
    out.columns.push_back({c.name, c.quantity, c.quantity == "acceleration" ? "m/s^2" : "V", true, c.axial_m, c.angle_deg, &c.values, true});
  // A board without a tachometer loses its tracked speed once the rotor drops (the estimate is
  // NaN + lost, never a stale value): such a speed stream is not a measured channel of the
  // exchange format (finite numbers only), so it is kept as an extra, undeclared CSV column.
  const bool speed_measured =
      std::all_of(e.speed_hz.begin(), e.speed_hz.end(), [](double v) { return std::isfinite(v); });
  if (!e.speed_hz.empty())
    out.columns.push_back({"speed_hz", "speed", "Hz", false, 0, 0, &e.speed_hz, speed_measured});
  // Beside a tachometer channel, the board's own speed estimate (e.g. the tracker's, NaN where
  // lost) is an extra, undeclared column: one speed channel per record.
  if (!e.speed_estimate_hz.empty())
    out.columns.push_back({"speed_estimate_hz", "speed", "Hz", false, 0, 0, &e.speed_estimate_hz, false});
  for (const auto& c : e.current_demand) out.columns.push_back({"demand_" + c.name, "current", "A", false, 0, 0, &c.values, false});
  out.columns.push_back({"t_clock_s", "time", "s", false, 0, 0, &e.t_s, false});
  write_measured_event(stem, out);
}

}  // namespace amb::host
