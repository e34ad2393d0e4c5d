#pragma once
// TOML text screening (board files, and the host's study specs and machine profiles), before the
// TOML parser sees it.
//
// toml++ 3.3 (Debian 12's libtomlplusplus) classifies whitespace with a generated table that
// reaches __builtin_unreachable for many non-ASCII code points (U+00A1..U+0499 among them:
// µ, °, ±, Greek, Cyrillic) while it records a key or a value: undefined behaviour driven by a
// user's file (found by fuzz_board_toml under UBSan). Board files are therefore ASCII outside
// comments. Non-ASCII text inside a comment (units such as µm in a note) is harmless and kept
// out of the parser's way: each of its bytes is replaced by a space, so line and byte column
// of everything else are unchanged.
#include <string>
#include <string_view>

namespace amb::board {

/// Returns the text to hand to the TOML parser: `text` with non-ASCII bytes inside comments
/// blanked and a leading UTF-8 byte-order mark removed. Throws std::invalid_argument naming the
/// line and column (1-based, bytes) of the first non-ASCII byte outside a comment (in a key, a
/// value or a string); the caller adds the file's name.
std::string screen_toml_text(std::string_view text);

}  // namespace amb::board
