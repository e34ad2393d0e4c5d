#include "host-tools/core/io/mat_v5_check.hpp"

#include <zlib.h>

#include <cstring>
#include <stdexcept>

namespace amb::host {
namespace {

// MAT-file Level 5 data types (MATLAB "MAT-File Format", table 1-1) and array classes.
enum : std::uint32_t {
  kMiInt8 = 1, kMiUint8 = 2, kMiInt16 = 3, kMiUint16 = 4, kMiInt32 = 5, kMiUint32 = 6,
  kMiSingle = 7, kMiDouble = 9, kMiInt64 = 12, kMiUint64 = 13, kMiMatrix = 14,
  kMiCompressed = 15, kMiUtf8 = 16, kMiUtf16 = 17, kMiUtf32 = 18,
};
enum : std::uint32_t {
  kMxCell = 1, kMxStruct = 2, kMxObject = 3, kMxChar = 4, kMxSparse = 5,
  kMxDouble = 6, kMxUint64 = 15, kMxFunction = 16, kMxOpaque = 17,
};
constexpr std::uint32_t kComplexFlag = 0x0800;
constexpr std::uint64_t kMaxElements = std::uint64_t{1} << 48;

/// Bytes per element of a numeric data type, 0 for a non-numeric one.
std::size_t element_bytes(std::uint32_t type) {
  switch (type) {
    case kMiInt8: case kMiUint8: case kMiUtf8: return 1;
    case kMiInt16: case kMiUint16: case kMiUtf16: return 2;
    case kMiInt32: case kMiUint32: case kMiSingle: case kMiUtf32: return 4;
    case kMiDouble: case kMiInt64: case kMiUint64: return 8;
    default: return 0;
  }
}

struct Tag {
  std::uint32_t type = 0;
  std::uint32_t nbytes = 0;
  std::size_t data = 0;  ///< offset of the element's data
  std::size_t next = 0;  ///< offset of the next element (padded to 8 bytes)
};

/// Walks one buffer (the file, or one inflated compressed variable).
class Walker {
 public:
  Walker(const std::uint8_t* base, std::size_t size, bool swap, std::string where)
      : base_(base), size_(size), swap_(swap), where_(std::move(where)) {}

  std::uint32_t u32(std::size_t off) const {
    std::uint32_t v;
    std::memcpy(&v, base_ + off, 4);
    return swap_ ? __builtin_bswap32(v) : v;
  }

  [[noreturn]] void fail(std::size_t off, const std::string& why) const {
    throw std::runtime_error(where_ + " byte " + std::to_string(off) + ": " + why);
  }

  /// The tag at `off`, whose element must end at or before `end`.
  Tag tag(std::size_t off, std::size_t end, const char* what) const {
    if (end < off || end - off < 8)
      fail(off, std::string(what) + ": no room for an element tag (" + std::to_string(end - off) + " bytes left)");
    Tag t;
    const std::uint32_t first = u32(off);
    if ((first >> 16) != 0) {  // small data element: size and type packed in 4 bytes
      t.type = first & 0xFFFF;
      t.nbytes = first >> 16;
      if (t.nbytes > 4) fail(off, std::string(what) + ": small element declares " + std::to_string(t.nbytes) + " bytes (at most 4)");
      t.data = off + 4;
      t.next = off + 8;
      return t;
    }
    t.type = first;
    t.nbytes = u32(off + 4);
    t.data = off + 8;
    if (t.nbytes > end - t.data)
      fail(off, std::string(what) + " declares " + std::to_string(t.nbytes) + " bytes but only " +
                    std::to_string(end - t.data) + " remain in its parent");
    const std::size_t padded = (static_cast<std::size_t>(t.nbytes) + 7) & ~std::size_t{7};
    t.next = (padded <= end - t.data) ? t.data + padded : end;
    return t;
  }

  /// Content of an miMATRIX element: [data, end).
  void matrix(std::size_t data, std::size_t end, int depth) const {
    if (depth > kMaxMatNestingDepth) fail(data, "nesting deeper than " + std::to_string(kMaxMatNestingDepth) + " levels");
    if (data == end) return;  // an empty array (e.g. an empty cell element)
    const Tag flags = tag(data, end, "array flags");
    if (flags.type != kMiUint32 || flags.nbytes < 8) fail(data, "array flags are not 8 bytes of miUINT32");
    const std::uint32_t flag_word = u32(flags.data);
    const std::uint32_t cls = flag_word & 0xFF;
    const bool complex = (flag_word & kComplexFlag) != 0;
    // A function handle is no recording, and libmatio reads its header (a name tag of any
    // claimed size) before anything else is checked (fuzz_mat_file: a 1.1 GB name in a 326-byte
    // file, allocated and zeroed). An opaque object (MCOS: name, type system, class name, then
    // its data) is kept, each of its tags bounded by its parent.
    if (cls == kMxFunction) fail(data, "a function handle (array class 16) is not recorded data");
    if (cls == kMxOpaque) {
      const std::size_t q = tag(flags.next, end, "opaque object name").next;
      (void)tag(tag(q, end, "opaque type system").next, end, "opaque class name");
      return;
    }
    const Tag dims = tag(flags.next, end, "dimensions");
    if (dims.type != kMiInt32 || dims.nbytes % 4 != 0 || dims.nbytes < 8)
      fail(flags.next, "dimensions are not at least two miINT32 values");
    std::uint64_t count = 1;
    for (std::size_t i = 0; i < dims.nbytes / 4; ++i) {
      const auto d = static_cast<std::int32_t>(u32(dims.data + 4 * i));
      if (d < 0) fail(dims.data + 4 * i, "negative dimension " + std::to_string(d));
      if (d != 0 && count > kMaxElements / static_cast<std::uint64_t>(d))
        fail(dims.data, "dimensions multiply beyond 2^48 elements");
      count *= static_cast<std::uint64_t>(d);
    }
    const Tag name = tag(dims.next, end, "array name");
    if (name.type != kMiInt8 && name.type != kMiUtf8) fail(dims.next, "array name is not miINT8 text");
    std::size_t p = name.next;
    switch (cls) {
      case kMxCell: children(p, end, count, depth, "cell"); return;
      case kMxStruct:
      case kMxObject: {
        if (cls == kMxObject) p = tag(p, end, "class name").next;
        const Tag len = tag(p, end, "field name length");
        if (len.type != kMiInt32 || len.nbytes != 4) fail(p, "field name length is not one miINT32");
        const std::uint32_t field_len = u32(len.data);
        const Tag names = tag(len.next, end, "field names");
        if (names.type != kMiInt8) fail(len.next, "field names are not miINT8 text");
        if (field_len == 0 && names.nbytes != 0) fail(len.next, "field names with a field name length of 0");
        const std::uint64_t fields = field_len ? names.nbytes / field_len : 0;
        if (fields != 0 && count > kMaxElements / fields) fail(p, "struct elements x fields overflow");
        children(names.next, end, count * fields, depth, "struct field");
        return;
      }
      case kMxChar:
        data_part(p, end, count, "characters");
        return;
      case kMxSparse: {
        // Row indices, column starts, values: sizes follow nzmax, only the bounds matter here.
        std::size_t q = tag(p, end, "sparse row indices").next;
        q = tag(q, end, "sparse column starts").next;
        q = tag(q, end, "sparse values").next;
        if (complex) (void)tag(q, end, "sparse imaginary values");
        return;
      }
      default:
        if (cls < kMxDouble || cls > kMxUint64) fail(data, "unknown array class " + std::to_string(cls));
        p = data_part(p, end, count, "real part");
        if (complex) (void)data_part(p, end, count, "imaginary part");
        return;
    }
  }

 private:
  /// A numeric data element that must hold at least `count` values; returns the next offset.
  std::size_t data_part(std::size_t off, std::size_t end, std::uint64_t count, const char* what) const {
    const Tag t = tag(off, end, what);
    const std::size_t each = element_bytes(t.type);
    if (each == 0) fail(off, std::string(what) + ": data type " + std::to_string(t.type) + " is not numeric");
    if (t.nbytes / each < count)
      fail(off, std::string(what) + ": dimensions declare " + std::to_string(count) + " elements but the data holds " +
                    std::to_string(t.nbytes / each));
    return t.next;
  }

  /// `count` nested miMATRIX elements (cells or struct fields) starting at `off`.
  void children(std::size_t off, std::size_t end, std::uint64_t count, int depth, const char* what) const {
    if (count > (end - off) / 8)
      fail(off, std::to_string(count) + " " + what + " elements declared, room for at most " + std::to_string((end - off) / 8));
    for (std::uint64_t i = 0; i < count; ++i) {
      const Tag t = tag(off, end, what);
      if (t.type != kMiMatrix) fail(off, std::string(what) + " element is not an miMATRIX");
      matrix(t.data, t.data + t.nbytes, depth + 1);
      off = t.next;
    }
  }

  const std::uint8_t* base_;
  std::size_t size_;
  bool swap_;
  std::string where_;
};

std::vector<std::uint8_t> inflate_variable(const std::uint8_t* in, std::size_t n, const std::string& where) {
  std::vector<std::uint8_t> out;
  z_stream zs{};
  if (inflateInit(&zs) != Z_OK) throw std::runtime_error(where + ": zlib cannot start");
  zs.next_in = const_cast<Bytef*>(in);
  zs.avail_in = static_cast<uInt>(n);
  constexpr std::size_t kChunk = 1 << 16;
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    if (out.size() >= kMaxMatInflatedBytes) {
      inflateEnd(&zs);
      throw std::runtime_error(where + ": inflates beyond " + std::to_string(kMaxMatInflatedBytes >> 20) + " MiB");
    }
    const std::size_t have = out.size();
    out.resize(have + kChunk);
    zs.next_out = out.data() + have;
    zs.avail_out = static_cast<uInt>(kChunk);
    rc = inflate(&zs, Z_NO_FLUSH);
    out.resize(have + (kChunk - zs.avail_out));
    if (rc == Z_BUF_ERROR && zs.avail_in == 0) break;  // truncated stream: check what inflated
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) {
      inflateEnd(&zs);
      throw std::runtime_error(where + ": corrupt compressed data (zlib: " + (zs.msg ? zs.msg : "error") + ")");
    }
  }
  inflateEnd(&zs);
  return out;
}

}  // namespace

MatContainer check_mat_structure(const std::vector<std::uint8_t>& bytes, const std::string& file) {
  if (bytes.size() < 128)
    throw std::runtime_error(file + ": shorter than the 128-byte MAT-file header (MAT v4 files are not supported)");
  bool swap;
  if (bytes[126] == 'I' && bytes[127] == 'M') swap = false;
  else if (bytes[126] == 'M' && bytes[127] == 'I') swap = true;
  else throw std::runtime_error(file + ": no endian indicator 'IM'/'MI' at byte 126 (not a MATLAB 5 or later file; MAT v4 is not supported)");
  std::uint16_t version;
  std::memcpy(&version, bytes.data() + 124, 2);
  if (swap) version = __builtin_bswap16(version);
  if (version == 0x0200) {
    static const char kHdf5Signature[] = "\x89HDF\r\n\x1a\n";
    if (bytes.size() < 520 || std::memcmp(bytes.data() + 512, kHdf5Signature, 8) != 0)
      throw std::runtime_error(file + ": MAT 7.3 header without an HDF5 signature at byte 512");
    return MatContainer::Hdf5;
  }
  if (version != 0x0100) throw std::runtime_error(file + ": unknown MAT-file version 0x" + std::to_string(version));

  const Walker top(bytes.data(), bytes.size(), swap, file + ":");
  std::size_t p = 128;
  while (bytes.size() - p >= 8) {
    const Tag t = top.tag(p, bytes.size(), "variable");
    if (t.type == kMiMatrix) {
      top.matrix(t.data, t.data + t.nbytes, 0);
      p = t.next;
    } else if (t.type == kMiCompressed) {
      const std::string where = file + ": compressed variable at byte " + std::to_string(p) + ", inflated";
      const std::vector<std::uint8_t> inner = inflate_variable(bytes.data() + t.data, t.nbytes, where);
      const Walker sub(inner.data(), inner.size(), swap, where);
      const Tag m = sub.tag(0, inner.size(), "variable");
      if (m.type != kMiMatrix) sub.fail(0, "compressed element does not hold an miMATRIX");
      sub.matrix(m.data, m.data + m.nbytes, 0);
      p = t.data + t.nbytes;  // compressed elements are not padded
    } else {
      top.fail(p, "top-level element of data type " + std::to_string(t.type) + " (expected miMATRIX or miCOMPRESSED)");
    }
  }
  return MatContainer::Level5;
}

}  // namespace amb::host
