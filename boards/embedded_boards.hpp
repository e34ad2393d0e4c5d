#pragma once
// Board files compiled into the executables (see boards/CMakeLists.txt).
namespace amb::boards {

struct EmbeddedBoard {
  const char* name;  ///< file stem, e.g. "bath-amb-rig"; nullptr terminates the table
  const char* toml;  ///< the file's text
};

/// The table of embedded boards, terminated by an entry whose name is nullptr.
const EmbeddedBoard* embedded_boards();

/// The board every executable uses when none is named.
inline constexpr const char* k_default_board = "bath-amb-rig";

}  // namespace amb::boards
