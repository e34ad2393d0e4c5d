// Board files come from users: any byte sequence must either parse into a validated
// BoardConfig or be refused with a BoardError naming what was wrong. Anything else (a crash,
// a sanitizer report, another exception type) is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "firmware/board/board.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto board = amb::board::parse_board(text, "fuzz.toml");
    (void)board;
  } catch (const amb::board::BoardError& e) {
    if (e.what()[0] == '\0') __builtin_trap();  // a refusal must say why
  }
  return 0;
}
