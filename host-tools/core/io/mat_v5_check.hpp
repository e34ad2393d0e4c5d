#pragma once
// Structural check of a MATLAB Level-5 .mat file before libmatio sees it.
//
// libmatio trusts the sizes a file declares: it reserves memory for a dimension list, a
// name or a struct's fields from the tag before it reads them (a 4 kB file can make it ask
// for gigabytes, found by fuzzing). Measured recordings come from outside, so the reader
// walks the element tree first and refuses any tag that claims more bytes than its parent
// holds, dimensions whose element count the data cannot hold, and nesting deeper than
// `kMaxMatNestingDepth`. Compressed variables (miCOMPRESSED) are inflated (zlib) up to
// `kMaxMatInflatedBytes` and checked the same way.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace amb::host {

/// Deepest struct/cell nesting accepted (MATLAB files from rigs use a handful of levels).
inline constexpr int kMaxMatNestingDepth = 32;
/// Largest inflated size of one compressed variable, bytes (1 GiB).
inline constexpr std::size_t kMaxMatInflatedBytes = std::size_t{1} << 30;

/// Which container the file is, as far as the reader is concerned.
enum class MatContainer {
  Level5,  ///< MATLAB 5/6/7 (checked element by element)
  Hdf5,    ///< MATLAB 7.3 (HDF5; libhdf5 validates its own structure)
};

/// Check `bytes` (a whole file's content) and return its container. Throws
/// std::runtime_error whose message starts with `file` and names the offending element
/// (byte offset, what it declared, what was available) if the structure is not sound.
/// MAT v4 files (no 128-byte header) are refused: they carry no structure to check.
MatContainer check_mat_structure(const std::vector<std::uint8_t>& bytes, const std::string& file);

}  // namespace amb::host
