#include "host-tools/amb-host/cli_checks.hpp"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "firmware/board/board.hpp"
#include "host-tools/core/io/file_kind.hpp"

namespace amb::host::cli {

namespace {

std::map<const CLI::Option*, OptionInfo>& registry() {
  static std::map<const CLI::Option*, OptionInfo> r;
  return r;
}

bool is_embedded_board(const std::string& name) {
  for (const auto& n : amb::board::embedded_board_names())
    if (n == name) return true;
  return false;
}

std::string embedded_list() {
  std::string s;
  for (const auto& n : amb::board::embedded_board_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// Why `path` cannot be an input of `kind` ("" when it can be, as far as its first bytes tell).
std::string input_problem(const std::string& path, const std::string& kind) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (kind == "board" && is_embedded_board(path)) return {};
  const bool stem_ok = (kind == "event" || kind == "measured-event") && !fs::exists(path, ec) &&
                       fs::is_regular_file(path + ".json", ec);
  const std::string file = stem_ok ? path + ".json" : path;
  const std::string found = sniff_file_kind(file);
  if (found == "missing") {
    if (kind == "board")
      return "'" + path + "' is neither a board file nor an embedded board (" + embedded_list() + ")";
    return "file '" + path + "' does not exist";
  }
  if (found == "directory") return "'" + path + "' is a directory, not " + file_kind_phrase(kind);
  if (found == "empty") return "file '" + file + "' is empty";
  // Refuse a file that is recognisably of another kind; a file that is merely damaged is left
  // to the command's own loader, which says what is wrong inside it.
  static const std::map<std::string, std::vector<std::string>> accepts = {
      {"ambe", {"ambe"}},
      {"event", {"ambe", "measured-event", "csv"}},
      {"measured-event", {"measured-event", "csv"}},
      {"mat", {"mat"}},
      {"board", {"board", "toml"}},
      {"profile", {"profile", "toml"}},
      {"envelope-spec", {"envelope-spec", "toml"}},
      {"wear-record", {"wear-record"}},
      {"hybrid-model", {"hybrid-model", "json"}},
  };
  const auto it = accepts.find(kind);
  if (it == accepts.end()) return {};
  for (const auto& k : it->second)
    if (k == found) return {};
  if (found == "unknown" && kind != "ambe" && kind != "wear-record" && kind != "mat") return {};
  return "'" + file + "' is " + file_kind_phrase(found) + ", not " + file_kind_phrase(kind);
}

}  // namespace

CLI::Option* number(CLI::Option* o, amb::cli::NumberRange r) {
  CLI::Validator v(
      [r](std::string& text) { return amb::cli::check_number(text, r); }, amb::cli::describe(r), "number");
  o->check(v);
  o->capture_default_str();
  registry()[o].range = r;
  return o;
}

CLI::Option* real(CLI::Option* o, double lo, double hi, const char* unit) {
  return number(o, amb::cli::NumberRange{lo, hi, false, false, unit});
}

CLI::Option* positive(CLI::Option* o, double hi, const char* unit) {
  return number(o, amb::cli::NumberRange{0.0, hi, true, false, unit});
}

CLI::Option* whole(CLI::Option* o, double lo, double hi) { return number(o, amb::cli::NumberRange{lo, hi, false, true, ""}); }

CLI::Option* input_file(CLI::Option* o, const std::string& kind) {
  CLI::Validator v([kind](std::string& path) { return input_problem(path, kind); }, kind, "input_" + kind);
  o->check(v);
  registry()[o].file_kind = kind;
  return o;
}

CLI::Option* output_path(CLI::Option* o) {
  o->capture_default_str();
  registry()[o].output = true;
  return o;
}

CLI::Option* output_file(CLI::Option* o) {
  CLI::Validator v(
      [](std::string& path) -> std::string {
        namespace fs = std::filesystem;
        std::error_code ec;
        const fs::path parent = fs::path(path).parent_path();
        if (path.empty()) return "an empty path";
        if (!parent.empty() && !fs::is_directory(parent, ec))
          return "'" + path + "': folder '" + parent.string() + "' does not exist";
        return {};
      },
      "", "output_file");
  o->check(v);
  output_path(o);
  registry()[o].output_file = true;
  return o;
}

std::string in_option_names(std::string message,
                            std::initializer_list<std::pair<const char*, const char*>> internal_to_option) {
  auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; };
  for (const auto& [internal, option] : internal_to_option) {
    const std::string from = internal;
    for (size_t p = message.find(from); p != std::string::npos; p = message.find(from, p)) {
      const bool starts = p == 0 || !word_char(message[p - 1]);
      const bool ends = p + from.size() >= message.size() || !word_char(message[p + from.size()]) ||
                        (message[p + from.size()] == '.' && p + from.size() + 1 == message.size());
      if (starts && ends) {
        message.replace(p, from.size(), option);
        p += std::char_traits<char>::length(option);
      } else {
        p += from.size();
      }
    }
  }
  return message;
}

const OptionInfo* info(const CLI::Option* o) {
  const auto it = registry().find(o);
  return it == registry().end() ? nullptr : &it->second;
}

uint32_t arm_key(const std::string& option_value, const std::string& board, const std::string& when_missing) {
  auto parse = [](const std::string& text, const char* from) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 0);
    if (text.empty() || *end != '\0' || v == 0 || v > 0xFFFFFFFFull)
      throw std::invalid_argument(std::string("arm key from ") + from + " must be an integer in [1, 2^32-1], got '" + text + "'");
    return static_cast<uint32_t>(v);
  };
  if (!option_value.empty()) return parse(option_value, "--arm-key");
  if (!board.empty()) {
    const amb::board::BoardConfig b = amb::board::load_board(board);
    if (b.comms.modbus.arm_key == 0)
      throw std::invalid_argument("board " + b.name + " has no [comms.modbus] arm_key: it takes no commands over Modbus");
    return b.comms.modbus.arm_key;
  }
  if (const char* env = std::getenv("AMB_ARM_KEY"); env && *env) return parse(env, "AMB_ARM_KEY");
  throw std::invalid_argument(when_missing);
}

}  // namespace amb::host::cli
