// MATLAB files (measured recordings) come from outside. The input is written as a .mat file
// and read through the project's reader (libmatio underneath): list the variables, read each
// as a matrix and as a vector. Every malformed file must end in a std::exception with a
// message; a crash or a sanitizer report in the reader or in libmatio is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

#include "host-tools/core/io/mat_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = [] {
    char tmpl[] = "/tmp/amb-fuzz-mat-XXXXXX";
    const char* d = mkdtemp(tmpl);
    return std::string(d ? d : "/tmp") + "/input.mat";
  }();
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size) std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    for (const auto& name : amb::host::list_mat_variables(path)) {
      try {
        (void)amb::host::read_mat_matrix(path, name);
      } catch (const std::exception&) {
      }
      try {
        (void)amb::host::read_mat_vector(path, name);
      } catch (const std::exception&) {
      }
    }
  } catch (const std::exception& ex) {
    if (ex.what()[0] == '\0') __builtin_trap();
  }
  return 0;
}
