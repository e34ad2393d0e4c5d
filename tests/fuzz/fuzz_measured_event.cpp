// Measured events come from any user's DAQ export: a JSON sidecar and a CSV file. The input
// is cut at the first NUL byte into the sidecar (before) and the CSV (after), both written to
// a scratch directory, and imported. The importer must either load the event or refuse it
// with a message (std::exception); a crash, a sanitizer report or a silent partial import is
// a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "host-tools/core/events/measured_event.hpp"

namespace {

const std::string& scratch_dir() {
  static const std::string dir = [] {
    char tmpl[] = "/tmp/amb-fuzz-measured-XXXXXX";
    const char* d = mkdtemp(tmpl);
    return std::string(d ? d : "/tmp");
  }();
  return dir;
}

void write_file(const std::string& path, const uint8_t* p, size_t n) {
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    if (n) std::fwrite(p, 1, n, f);
    std::fclose(f);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
  const size_t json_n = nul ? static_cast<size_t>(nul - data) : size;
  const std::string stem = scratch_dir() + "/event";
  write_file(stem + ".json", data, json_n);
  write_file(stem + ".csv", nul ? nul + 1 : data + size, nul ? size - json_n - 1 : 0);
  try {
    const auto e = amb::host::read_measured_event(stem + ".json");
    (void)e;
  } catch (const std::exception& ex) {
    if (ex.what()[0] == '\0') __builtin_trap();
  }
  return 0;
}
