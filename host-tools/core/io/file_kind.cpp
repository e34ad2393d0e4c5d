#include "host-tools/core/io/file_kind.hpp"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

namespace amb::host {

namespace {

std::string toml_kind(const std::string& path) {
  toml::table t;
  try {
    t = toml::parse_file(path);
  } catch (const std::exception&) {
    return "unknown";  // not TOML: the command's own loader says where it breaks
  }
  if (t.contains("board") && t.contains("rig")) return "board";
  if (const auto s = t["schema"].value<std::string>(); s && s->rfind("amb-machine/", 0) == 0) return "profile";
  if (t.contains("study")) return "envelope-spec";
  return "toml";
}

std::string json_kind(const std::string& path) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return "unknown";
  const std::string format = j.value("format", std::string());
  if (format.rfind("amb-measured-event/", 0) == 0) return "measured-event";
  if (format.rfind("amb-hybrid-model", 0) == 0) return "hybrid-model";
  return "json";
}

}  // namespace

std::string sniff_file_kind(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) return "missing";
  if (fs::is_directory(path, ec)) return "directory";
  if (fs::file_size(path, ec) == 0 && !ec) return "empty";
  std::ifstream in(path, std::ios::binary);
  char head[128] = {};
  in.read(head, sizeof head);
  const std::string h(head, static_cast<size_t>(in.gcount()));
  if (h.rfind("AMBE", 0) == 0) return "ambe";
  if (h.rfind("AMBW", 0) == 0) return "wear-record";
  if (h.rfind("MATLAB 5.0", 0) == 0) return "mat";
  const std::string ext = fs::path(path).extension().string();
  const size_t first = h.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (h[first] == '{' || h[first] == '[') && ext == ".json") return json_kind(path);
  if (ext == ".toml") return toml_kind(path);
  if (ext == ".csv") return "csv";
  if (first != std::string::npos && h[first] == '{') return json_kind(path);
  return "unknown";
}

std::string file_kind_phrase(const std::string& kind) {
  if (kind == "ambe") return "a board event (AMBE)";
  if (kind == "wear-record") return "a wear record (AMBW)";
  if (kind == "mat") return "a MATLAB .mat file";
  if (kind == "measured-event") return "a measured event (amb-measured-event/1)";
  if (kind == "event") return "an event (AMBE, or a measured event .json/.csv)";
  if (kind == "hybrid-model") return "a hybrid model (amb-hybrid-model)";
  if (kind == "board") return "a board file";
  if (kind == "profile") return "a machine profile (amb-machine/1)";
  if (kind == "envelope-spec") return "an envelope study spec";
  if (kind == "json") return "a JSON file";
  if (kind == "toml") return "a TOML file";
  if (kind == "csv") return "a CSV file";
  if (kind == "empty") return "an empty file";
  if (kind == "missing") return "a missing file";
  if (kind == "directory") return "a directory";
  return "a file of unknown kind";
}

}  // namespace amb::host
