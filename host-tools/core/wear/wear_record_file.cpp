#include "host-tools/core/wear/wear_record_file.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace amb::host::wear {

fw::WearRecord read_wear_record_file(const std::string& path, const std::string& expected_board) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot open wear record '" + path + "'");
  // A record is a few kB (fw::wear_record_size()); anything much larger is not one: read
  // a bounded prefix so a wrong file cannot exhaust memory, the decoder names the size.
  std::vector<uint8_t> bytes;
  const size_t limit = 4 * fw::wear_record_size();
  std::istreambuf_iterator<char> it(in), end;
  for (; it != end && bytes.size() < limit; ++it) bytes.push_back(static_cast<uint8_t>(*it));
  if (it != end)
    throw std::invalid_argument("'" + path + "' is not a usable wear record (AMBW v1): larger than " + std::to_string(limit) +
                                " bytes (a record has " + std::to_string(fw::wear_record_size()) + ")");
  fw::WearRecord r;
  std::string err;
  if (!fw::decode_wear_record(bytes, r, err))
    throw std::invalid_argument("'" + path + "' is not a usable wear record (AMBW v1): " + err);
  if (!expected_board.empty() && r.board_name != expected_board)
    throw std::invalid_argument("'" + path + "' is the wear record of board '" + r.board_name + "', not of '" +
                                expected_board + "'");
  return r;
}

std::string wear_record_path_problem(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    return "'" + path + "': folder '" + parent.string() + "' does not exist";
  return {};
}

void write_wear_record_file(const std::string& path, const fw::WearRecord& record) {
  const std::vector<uint8_t> bytes = fw::encode_wear_record(record);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error("wear record '" + path + "' cannot be written");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("wear record '" + path + "' cannot be written: " + ec.message());
  }
}

}  // namespace amb::host::wear
