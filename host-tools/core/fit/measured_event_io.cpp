#include "host-tools/core/fit/measured_event_io.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

namespace amb::host::fit {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void refuse(const std::string& file, const std::string& what) {
  throw MeasuredEventError(file + ": " + what);
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) refuse(path, "cannot open");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    refuse(path, std::string("not valid JSON: ") + e.what());
  }
}

std::string sidecar_path(const std::string& p) {
  fs::path f(p);
  if (f.extension() == ".csv") f.replace_extension(".json");
  return f.string();
}

double length_scale(const std::string& unit, const std::string& file, const std::string& column) {
  if (unit == "m") return 1.0;
  if (unit == "mm") return 1e-3;
  if (unit == "um") return 1e-6;
  refuse(file, "channel '" + column + "': unknown displacement unit '" + unit + "' (m, mm, um)");
}

double angle_diff_deg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return std::abs(d);
}

}  // namespace

std::string measured_event_rig(const std::string& json_path) {
  const std::string path = sidecar_path(json_path);
  const auto j = read_json(path);
  if (!j.contains("rig") || !j["rig"].is_string()) refuse(path, "field 'rig' (string) is required");
  return j["rig"].get<std::string>();
}

DropMeasurement read_measured_event(const std::string& json_path, const model::PlantParams& rig) {
  const std::string path = sidecar_path(json_path);
  const auto j = read_json(path);
  auto need = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key)) refuse(path, std::string("field '") + key + "' is required");
    return j[key];
  };
  if (!need("format").is_string() || j["format"].get<std::string>() != "amb-measured-event/1")
    refuse(path, "field 'format' must be \"amb-measured-event/1\"");
  DropMeasurement m;
  m.source = path;
  m.rig = need("rig").is_string() ? j["rig"].get<std::string>() : "";
  if (!need("sample_rate_hz").is_number() || !(j["sample_rate_hz"].get<double>() > 0.0))
    refuse(path, "field 'sample_rate_hz' must be a number > 0");
  m.sample_rate_hz = j["sample_rate_hz"].get<double>();
  if (!need("trigger_index").is_number_integer() || j["trigger_index"].get<long>() < 0)
    refuse(path, "field 'trigger_index' must be an integer >= 0");
  m.trigger_index = static_cast<int>(j["trigger_index"].get<long>());
  if (j.contains("speed_rpm")) {
    if (!j["speed_rpm"].is_number()) refuse(path, "field 'speed_rpm' must be a number");
    m.speed_at_trigger_hz = j["speed_rpm"].get<double>() / 60.0;
  }
  if (j.contains("declared_faults")) {
    if (!j["declared_faults"].is_array()) refuse(path, "field 'declared_faults' must be a list");
    m.amplifiers_off = false;
    for (const auto& f : j["declared_faults"]) {
      const std::string name = f.is_string() ? f.get<std::string>() : "";
      if (name == "amb_cutoff_all") m.amplifiers_off = true;
      else refuse(path, "declared fault '" + f.dump() + "' is not understood by the fit (known: amb_cutoff_all)");
    }
    if (j["declared_faults"].empty()) m.amplifiers_off = true;  // nothing declared: the drop of an AMB switch-off
  }

  // Channels: which CSV column feeds which sensor, and the scale to SI.
  struct Use {
    int sensor = -1;  // 0..3, or 4 = speed
    double scale = 1.0;
  };
  std::map<std::string, Use> use;
  if (!need("channels").is_array()) refuse(path, "field 'channels' must be a list");
  for (size_t c = 0; c < j["channels"].size(); ++c) {
    const auto& ch = j["channels"][c];
    const std::string where = "channels[" + std::to_string(c) + "]";
    if (!ch.contains("column") || !ch["column"].is_string()) refuse(path, where + ".column (string) is required");
    if (!ch.contains("quantity") || !ch["quantity"].is_string()) refuse(path, where + ".quantity (string) is required");
    if (!ch.contains("unit") || !ch["unit"].is_string()) refuse(path, where + ".unit (string) is required");
    const std::string col = ch["column"], q = ch["quantity"], unit = ch["unit"];
    if (q == "displacement") {
      if (!ch.contains("axial_m") || !ch["axial_m"].is_number() || !ch.contains("angle_deg") || !ch["angle_deg"].is_number())
        refuse(path, where + ": a displacement channel needs axial_m and angle_deg");
      const double z = ch["axial_m"], a = ch["angle_deg"];
      int found = -1;
      for (size_t s = 0; s < 4; ++s)
        if (std::abs(rig.sensor[s].axial_m - z) <= 5e-3 && angle_diff_deg(rig.sensor[s].angle_deg, a) <= 1.0) found = static_cast<int>(s);
      if (found < 0) refuse(path, where + " ('" + col + "'): no sensor of the rig at axial " + std::to_string(z) + " m, angle " + std::to_string(a) + " deg");
      use[col] = Use{found, length_scale(unit, path, col)};
    } else if (q == "speed") {
      double sc = 0.0;
      if (unit == "rpm") sc = 2.0 * M_PI / 60.0;
      else if (unit == "Hz") sc = 2.0 * M_PI;
      else refuse(path, where + ": unknown speed unit '" + unit + "' (rpm, Hz)");
      use[col] = Use{4, sc};
    }
  }
  std::array<bool, 5> have{};
  for (const auto& [col, u] : use) have[static_cast<size_t>(u.sensor)] = true;
  for (size_t s = 0; s < 4; ++s)
    if (!have[s]) refuse(path, "no displacement channel for sensor " + std::to_string(s) + " of the rig (axial " +
                               std::to_string(rig.sensor[s].axial_m) + " m, angle " + std::to_string(rig.sensor[s].angle_deg) + " deg)");

  // CSV.
  fs::path csv = fs::path(path).replace_extension(".csv");
  std::ifstream in(csv);
  if (!in) refuse(csv.string(), "cannot open (the CSV must sit next to the sidecar with the same stem)");
  std::string line;
  if (!std::getline(in, line)) refuse(csv.string(), "empty file");
  std::vector<int> col_use;  // per CSV column: index into `use` roles, -1 ignored
  std::vector<double> col_scale;
  {
    std::stringstream ss(line);
    std::string name;
    while (std::getline(ss, name, ',')) {
      if (!name.empty() && name.back() == '\r') name.pop_back();
      const auto it = use.find(name);
      col_use.push_back(it == use.end() ? -1 : it->second.sensor);
      col_scale.push_back(it == use.end() ? 1.0 : it->second.scale);
      if (it != use.end()) use.erase(it);
    }
  }
  if (!use.empty()) refuse(csv.string(), "column '" + use.begin()->first + "' named in the sidecar is missing from the header");
  long row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty() || line == "\r") continue;
    std::stringstream ss(line);
    std::string cell;
    std::array<double, 4> s{};
    double speed = 0.0;
    size_t c = 0;
    while (std::getline(ss, cell, ',')) {
      if (c < col_use.size() && col_use[c] >= 0) {
        char* end = nullptr;
        const double v = std::strtod(cell.c_str(), &end);
        if (end == cell.c_str() || !std::isfinite(v)) refuse(csv.string(), "row " + std::to_string(row) + ", column " + std::to_string(c + 1) + ": '" + cell + "' is not a number");
        if (col_use[c] == 4) speed = v * col_scale[c];
        else s[static_cast<size_t>(col_use[c])] = v * col_scale[c];
      }
      ++c;
    }
    if (c < col_use.size()) refuse(csv.string(), "row " + std::to_string(row) + " has " + std::to_string(c) + " cells, the header " + std::to_string(col_use.size()));
    m.sensor_m.push_back(s);
    if (have[4]) m.speed_rad_s.push_back(speed);
  }
  if (have[4] && m.speed_at_trigger_hz <= 0.0 && static_cast<size_t>(m.trigger_index) < m.speed_rad_s.size())
    m.speed_at_trigger_hz = m.speed_rad_s[static_cast<size_t>(m.trigger_index)] / (2.0 * M_PI);
  if (const std::string e = m.check(); !e.empty()) refuse(path, e);
  return m;
}

void write_measured_event(const std::string& stem, const DropMeasurement& m, const model::PlantParams& rig,
                          const std::string& notes) {
  nlohmann::json j;
  j["format"] = "amb-measured-event/1";
  j["rig"] = m.rig;
  j["sample_rate_hz"] = m.sample_rate_hz;
  j["trigger_index"] = m.trigger_index;
  j["speed_rpm"] = m.speed_at_trigger_hz * 60.0;
  nlohmann::json ch = nlohmann::json::array();
  ch.push_back({{"column", "t_s"}, {"quantity", "time"}, {"unit", "s"}});
  const char* names[4] = {"a1", "a2", "b1", "b2"};
  for (size_t s = 0; s < 4; ++s)
    ch.push_back({{"column", names[s]}, {"quantity", "displacement"}, {"unit", "um"}, {"axial_m", rig.sensor[s].axial_m},
                  {"angle_deg", rig.sensor[s].angle_deg}});
  if (!m.speed_rad_s.empty()) ch.push_back({{"column", "n"}, {"quantity", "speed"}, {"unit", "rpm"}});
  j["channels"] = ch;
  j["declared_faults"] = m.amplifiers_off ? nlohmann::json::array({"amb_cutoff_all"}) : nlohmann::json::array();
  j["notes"] = notes;
  std::ofstream js(stem + ".json");
  js << j.dump(2) << "\n";
  std::ofstream csv(stem + ".csv");
  csv << "t_s,a1,a2,b1,b2" << (m.speed_rad_s.empty() ? "" : ",n") << "\n";
  char buf[256];
  for (size_t i = 0; i < m.sensor_m.size(); ++i) {
    const double t = (static_cast<double>(i) - m.trigger_index) / m.sample_rate_hz;
    int n = std::snprintf(buf, sizeof buf, "%.6f,%.5f,%.5f,%.5f,%.5f", t, m.sensor_m[i][0] * 1e6, m.sensor_m[i][1] * 1e6,
                          m.sensor_m[i][2] * 1e6, m.sensor_m[i][3] * 1e6);
    if (!m.speed_rad_s.empty()) std::snprintf(buf + n, sizeof buf - static_cast<size_t>(n), ",%.4f", m.speed_rad_s[i] * 60.0 / (2.0 * M_PI));
    csv << buf << "\n";
  }
  if (!js || !csv) throw MeasuredEventError(stem + ": could not write the measured event");
}

}  // namespace amb::host::fit
