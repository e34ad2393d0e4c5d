#include "host-tools/core/residual/measured_record.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace amb::host::residual {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw std::runtime_error("measured event " + file + ": " + what);
}

double unit_factor(const std::string& file, const std::string& col, const std::string& unit) {
  static const std::map<std::string, double> k{
      {"s", 1.0}, {"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}, {"A", 1.0}, {"rpm", 1.0 / 60.0},
      {"Hz", 1.0}, {"m/s^2", 1.0}, {"g", 9.80665}, {"V", 1.0}};
  const auto it = k.find(unit);
  if (it == k.end()) fail(file, "channel '" + col + "': unknown unit '" + unit + "'");
  return it->second;
}

std::string csv_path_for(const std::string& sidecar) {
  std::filesystem::path p(sidecar);
  p.replace_extension(".csv");
  return p.string();
}

}  // namespace

MeasuredRecord read_measured_record(const std::string& sidecar_path) {
  std::ifstream js(sidecar_path);
  if (!js) fail(sidecar_path, "cannot open the sidecar");
  nlohmann::json j;
  try {
    js >> j;
  } catch (const std::exception& e) {
    fail(sidecar_path, std::string("not valid JSON: ") + e.what());
  }
  MeasuredRecord r;
  r.path = sidecar_path;
  auto need = [&](const char* key) -> const nlohmann::json& {
    if (!j.contains(key)) fail(sidecar_path, std::string("field '") + key + "' is required");
    return j.at(key);
  };
  if (need("format") != "amb-measured-event/1") fail(sidecar_path, "field 'format' must be \"amb-measured-event/1\"");
  try {
    r.rig = need("rig").get<std::string>();
    r.sample_rate_hz = need("sample_rate_hz").get<double>();
    r.trigger_index = need("trigger_index").get<long>();
    if (j.contains("speed_rpm") && !j["speed_rpm"].is_null()) r.speed_rpm = j["speed_rpm"].get<double>();
    if (j.contains("declared_faults")) r.declared_faults = j["declared_faults"].get<std::vector<std::string>>();
    if (j.contains("notes")) r.notes = j["notes"].get<std::string>();
    for (const auto& c : need("channels")) {
      RecordChannel ch;
      ch.column = c.at("column").get<std::string>();
      ch.quantity = c.at("quantity").get<std::string>();
      ch.unit = c.at("unit").get<std::string>();
      if (c.contains("axial_m")) ch.axial_m = c["axial_m"].get<double>();
      if (c.contains("angle_deg")) ch.angle_deg = c["angle_deg"].get<double>();
      r.channels.push_back(ch);
    }
  } catch (const nlohmann::json::exception& e) {
    fail(sidecar_path, std::string("bad field: ") + e.what());
  }
  if (!(r.sample_rate_hz > 0.0)) fail(sidecar_path, "field 'sample_rate_hz' must be > 0");

  const std::string csv = csv_path_for(sidecar_path);
  std::ifstream in(csv);
  if (!in) fail(csv, "cannot open the CSV");
  std::string line;
  if (!std::getline(in, line)) fail(csv, "empty file (a header row is required)");
  std::vector<std::string> header;
  {
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) header.push_back(cell);
  }
  std::vector<int> col_of(r.channels.size(), -1);
  std::vector<double> factor(r.channels.size(), 1.0);
  for (size_t i = 0; i < r.channels.size(); ++i) {
    for (size_t h = 0; h < header.size(); ++h)
      if (header[h] == r.channels[i].column) col_of[i] = static_cast<int>(h);
    if (col_of[i] < 0) fail(csv, "column '" + r.channels[i].column + "' named in the sidecar is missing");
    factor[i] = unit_factor(sidecar_path, r.channels[i].column, r.channels[i].unit);
  }
  std::vector<double> row(header.size());
  size_t row_no = 1;
  while (std::getline(in, line)) {
    ++row_no;
    if (line.empty()) continue;
    const char* p = line.c_str();
    for (size_t h = 0; h < header.size(); ++h) {
      char* end = nullptr;
      row[h] = std::strtod(p, &end);
      if (end == p) fail(csv, "row " + std::to_string(row_no) + ", column " + std::to_string(h + 1) + ": expected a number");
      p = end;
      if (h + 1 < header.size()) {
        if (*p != ',') fail(csv, "row " + std::to_string(row_no) + ": expected " + std::to_string(header.size()) + " columns");
        ++p;
      }
    }
    for (size_t i = 0; i < r.channels.size(); ++i)
      r.channels[i].values.push_back(row[static_cast<size_t>(col_of[i])] * factor[i]);
  }
  if (r.samples() < 2) fail(csv, "fewer than two data rows");
  return r;
}

void write_measured_record(const MeasuredRecord& r, const std::string& sidecar_path) {
  nlohmann::json j;
  j["format"] = "amb-measured-event/1";
  j["rig"] = r.rig;
  j["sample_rate_hz"] = r.sample_rate_hz;
  j["trigger_index"] = r.trigger_index;
  if (r.speed_rpm >= 0.0) j["speed_rpm"] = r.speed_rpm;
  j["declared_faults"] = r.declared_faults;
  j["notes"] = r.notes;
  j["channels"] = nlohmann::json::array();
  for (const auto& c : r.channels) {
    nlohmann::json cj{{"column", c.column}, {"quantity", c.quantity}, {"unit", c.unit}};
    if (c.quantity == "displacement" || c.quantity == "current" || c.quantity == "acceleration") {
      cj["axial_m"] = c.axial_m;
      cj["angle_deg"] = c.angle_deg;
    }
    j["channels"].push_back(cj);
  }
  {
    std::ofstream out(sidecar_path);
    if (!out) fail(sidecar_path, "cannot write");
    out << j.dump(2) << "\n";
  }
  const std::string csv = csv_path_for(sidecar_path);
  std::FILE* f = std::fopen(csv.c_str(), "w");
  if (!f) fail(csv, "cannot write");
  for (size_t i = 0; i < r.channels.size(); ++i) std::fprintf(f, "%s%s", i ? "," : "", r.channels[i].column.c_str());
  std::fprintf(f, "\n");
  for (size_t s = 0; s < r.samples(); ++s) {
    for (size_t i = 0; i < r.channels.size(); ++i) std::fprintf(f, "%s%.9g", i ? "," : "", r.channels[i].values[s]);
    std::fprintf(f, "\n");
  }
  std::fclose(f);
}

}  // namespace amb::host::residual
