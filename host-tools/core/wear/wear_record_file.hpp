#pragma once
// The wear record's file (AMBW, firmware/wear/wear_record.hpp) on the host: read and decoded,
// or encoded and written whole. Every host command and core path that reads or writes a wear
// record file goes through here.
#include <string>

#include "firmware/wear/wear_record.hpp"

namespace amb::host::wear {

/// Reads and decodes the wear record at `path`. `expected_board`: when not empty, the record
/// must be that board's. Throws std::invalid_argument naming the file and what is wrong
/// ("cannot open wear record 'P'", "'P' is not a usable wear record (AMBW v1): ...",
/// "'P' is the wear record of board 'A', not of 'B'").
fw::WearRecord read_wear_record_file(const std::string& path, const std::string& expected_board = {});

/// Empty when a wear record can be written at `path` (its folder exists), else why not.
std::string wear_record_path_problem(const std::string& path);

/// Encodes `record` and writes it to `path` whole or not at all (a temporary file `path`.tmp
/// renamed over the target). Throws std::runtime_error naming the file when it cannot be written.
void write_wear_record_file(const std::string& path, const fw::WearRecord& record);

}  // namespace amb::host::wear
