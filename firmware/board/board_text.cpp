#include "firmware/board/board_text.hpp"

#include <cstdio>
#include <stdexcept>

namespace amb::board {

std::string screen_toml_text(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::string out(text);
  enum class State { normal, comment, basic, literal, ml_basic, ml_literal };
  State st = State::normal;
  size_t line = 1, line_start = 0;
  auto refuse = [&](size_t i) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "line %zu, column %zu: non-ASCII byte 0x%02X outside a comment (ASCII only, except in "
                  "comments)",
                  line, i - line_start + 1, static_cast<unsigned>(static_cast<unsigned char>(text[i])));
    throw std::invalid_argument(msg);
  };
  auto starts = [&](size_t i, std::string_view s) { return text.substr(i, s.size()) == s; };
  for (size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      ++line;
      line_start = i + 1;
      // A newline ends a comment; inside a one-line string it is a TOML error the parser names.
      if (st == State::comment || st == State::basic || st == State::literal) st = State::normal;
      continue;
    }
    if (c >= 0x80) {
      if (st == State::comment) out[i] = ' ';
      else refuse(i);
      continue;
    }
    switch (st) {
      case State::normal:
        if (c == '#') st = State::comment;
        else if (starts(i, "\"\"\"")) st = State::ml_basic, i += 2;
        else if (starts(i, "'''")) st = State::ml_literal, i += 2;
        else if (c == '"') st = State::basic;
        else if (c == '\'') st = State::literal;
        break;
      case State::comment: break;
      case State::basic:
        if (c == '\\') {
          if (i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80) refuse(i + 1);
          if (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        } else if (c == '"') st = State::normal;
        break;
      case State::literal:
        if (c == '\'') st = State::normal;
        break;
      case State::ml_basic:
        if (c == '\\') {
          if (i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80) refuse(i + 1);
          if (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        } else if (starts(i, "\"\"\"")) st = State::normal, i += 2;
        break;
      case State::ml_literal:
        if (starts(i, "'''")) st = State::normal, i += 2;
        break;
    }
  }
  return out;
}

}  // namespace amb::board
