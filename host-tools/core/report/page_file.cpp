#include "host-tools/core/report/page_file.hpp"

#include "host-tools/core/report/svg_plot.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace amb::host::report {

std::string page_head(const std::string& title, const std::string& extra_css) {
  static const char* k_css = R"(body{font-family:sans-serif;margin:24px;color:#222;max-width:1320px}
h1{margin-bottom:4px}h2{border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:32px}
.sub{color:#555;margin-top:0}.row{display:flex;flex-wrap:wrap;gap:16px;align-items:flex-start}
svg.plot{border:1px solid #ddd;margin:6px 0}table.facts{border-collapse:collapse;margin:8px 0}
table.facts th{text-align:left;padding:2px 14px 2px 0;color:#444;font-weight:normal}
table.facts td{padding:2px 8px;font-family:monospace}.caption{color:#444;font-size:13px;max-width:1100px}
footer{margin-top:40px;color:#777;font-size:12px})";
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" + escape_xml(title) +
         "</title>\n<style>" + k_css + "\n" + extra_css + "</style>\n</head>\n<body>\n";
}

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
