#include "host-tools/core/report/page_file.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace amb::host::report {

std::string write_page_file(const std::string& html, const std::string& path, const std::string& what,
                            const std::string& open_hint) {
  namespace fs = std::filesystem;
  const fs::path p = fs::absolute(path);
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write the " + what + " to '" + p.string() + "'" + open_hint);
  out << html;
  out.close();
  if (!out) throw std::runtime_error("writing the " + what + " to '" + p.string() + "' failed (disk full?)");
  return p.string();
}

}  // namespace amb::host::report
