// The .mat structure check (host-tools/core/io/mat_v5_check.hpp) in front of libmatio:
// sound files pass and read back, files whose tags or dimensions claim more than they hold
// are refused with a message naming the element, before libmatio allocates anything.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host-tools/core/io/mat_file.hpp"
#include "host-tools/core/io/mat_v5_check.hpp"
#include "tests/support/test_paths.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;
namespace fs = std::filesystem;

void put32(Bytes& b, std::uint32_t v, bool big_endian) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (big_endian ? 24 - 8 * i : 8 * i)));
}
void put_f64(Bytes& b, double v, bool big_endian) {
  std::uint64_t u;
  std::memcpy(&u, &v, 8);
  for (int i = 0; i < 8; ++i) b.push_back(static_cast<std::uint8_t>(u >> (big_endian ? 56 - 8 * i : 8 * i)));
}
void pad8(Bytes& b) {
  while (b.size() % 8) b.push_back(0);
}

Bytes header(bool big_endian) {
  Bytes h(128, ' ');
  const char text[] = "MATLAB 5.0 MAT-file, written by the project's structure-check test";
  std::memcpy(h.data(), text, sizeof(text) - 1);
  for (int i = 116; i < 124; ++i) h[i] = 0;
  h[124] = big_endian ? 0x01 : 0x00;
  h[125] = big_endian ? 0x00 : 0x01;
  h[126] = big_endian ? 'M' : 'I';
  h[127] = big_endian ? 'I' : 'M';
  return h;
}

struct MatrixSpec {
  std::uint32_t rows = 2, cols = 3;
  std::uint32_t dims_tag_bytes = 8;  // the dims element's declared size
  std::size_t values = 6;            // doubles actually written
  std::string name = "x";
};

/// One miMATRIX element (tag + content) holding a double matrix.
Bytes double_matrix(const MatrixSpec& s, bool be) {
  Bytes c;
  put32(c, 6, be); put32(c, 8, be); put32(c, 6 /*mxDOUBLE*/, be); put32(c, 0, be);
  put32(c, 5, be); put32(c, s.dims_tag_bytes, be); put32(c, s.rows, be); put32(c, s.cols, be);
  put32(c, 1, be); put32(c, static_cast<std::uint32_t>(s.name.size()), be);
  c.insert(c.end(), s.name.begin(), s.name.end());
  pad8(c);
  put32(c, 9, be); put32(c, static_cast<std::uint32_t>(8 * s.values), be);
  for (std::size_t i = 0; i < s.values; ++i) put_f64(c, 1.5 * static_cast<double>(i), be);
  Bytes e;
  put32(e, 14, be);
  put32(e, static_cast<std::uint32_t>(c.size()), be);
  e.insert(e.end(), c.begin(), c.end());
  return e;
}

Bytes file_with(const Bytes& element, bool be = false) {
  Bytes f = header(be);
  f.insert(f.end(), element.begin(), element.end());
  return f;
}

Bytes compressed(const Bytes& element, bool be = false) {
  uLongf n = compressBound(element.size());
  Bytes z(n);
  EXPECT_EQ(compress(z.data(), &n, element.data(), element.size()), Z_OK);
  z.resize(n);
  Bytes e;
  put32(e, 15, be);
  put32(e, static_cast<std::uint32_t>(z.size()), be);
  e.insert(e.end(), z.begin(), z.end());
  return e;
}

std::string write_temp(const Bytes& b, const std::string& name) {
  const fs::path p = fs::path(amb::test::artefact_dir()) / "io" / name;
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  return p.string();
}

std::string refusal(const Bytes& b) {
  try {
    amb::host::check_mat_structure(b, "f.mat");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(MatStructure, SoundFileInBothByteOrdersPassesAndReadsBack) {
  for (const bool be : {false, true}) {
    const Bytes f = file_with(double_matrix({}, be), be);
    EXPECT_EQ(amb::host::check_mat_structure(f, "f.mat"), amb::host::MatContainer::Level5);
    const std::string path = write_temp(f, be ? "sound-be.mat" : "sound-le.mat");
    const auto m = amb::host::read_mat_matrix(path, "x");
    ASSERT_EQ(m.rows, 2u);
    ASSERT_EQ(m.cols, 3u);
    EXPECT_DOUBLE_EQ(m.values[5], 7.5);
  }
}

TEST(MatStructure, CompressedVariablePassesAndReadsBack) {
  const Bytes f = file_with(compressed(double_matrix({}, false)));
  EXPECT_EQ(amb::host::check_mat_structure(f, "f.mat"), amb::host::MatContainer::Level5);
  const auto m = amb::host::read_mat_matrix(write_temp(f, "compressed.mat"), "x");
  EXPECT_DOUBLE_EQ(m.values[4], 6.0);
}

TEST(MatStructure, DimensionsTheDataCannotHoldAreRefused) {
  MatrixSpec s;
  s.rows = 1000000;
  s.cols = 1000000;
  const std::string why = refusal(file_with(double_matrix(s, false)));
  EXPECT_NE(why.find("dimensions declare 1000000000000 elements but the data holds 6"), std::string::npos) << why;
  // Inside a compressed variable the same.
  const std::string why_z = refusal(file_with(compressed(double_matrix(s, false))));
  EXPECT_NE(why_z.find("compressed variable at byte 128"), std::string::npos) << why_z;
  EXPECT_NE(why_z.find("dimensions declare"), std::string::npos) << why_z;
}

TEST(MatStructure, TagClaimingMoreThanItsParentIsRefusedBeforeLibmatioAllocates) {
  MatrixSpec s;
  s.dims_tag_bytes = 0xFFFFFFF0u;  // a dimension list of a billion entries in a 100-byte file
  const Bytes f = file_with(double_matrix(s, false));
  const std::string why = refusal(f);
  EXPECT_NE(why.find("dimensions declares 4294967280 bytes but only"), std::string::npos) << why;
  // And through the public reader: an exception with that message, no allocation attempt.
  const std::string path = write_temp(f, "huge-dims.mat");
  EXPECT_THROW((void)amb::host::list_mat_variables(path), std::runtime_error);
}

TEST(MatStructure, TruncatedFileAndForeignHeadersAreRefused) {
  Bytes f = file_with(double_matrix({}, false));
  f.resize(f.size() - 16);  // the last two values cut off
  EXPECT_NE(refusal(f).find("declares"), std::string::npos);
  EXPECT_NE(refusal(Bytes(64, 0)).find("shorter than the 128-byte"), std::string::npos);
  Bytes v4 = header(false);
  v4[126] = 'X';
  EXPECT_NE(refusal(v4).find("MAT v4 is not supported"), std::string::npos);
}

TEST(MatStructure, StructDeclaringMoreFieldsThanItHoldsIsRefused) {
  // A 1x1 struct with field-name length 1 and 4000 one-character names, but no fields.
  Bytes c;
  put32(c, 6, false); put32(c, 8, false); put32(c, 2 /*mxSTRUCT*/, false); put32(c, 0, false);
  put32(c, 5, false); put32(c, 8, false); put32(c, 1, false); put32(c, 1, false);
  put32(c, (1u << 16) | 1u, false); c.push_back('s'); c.resize(c.size() + 3, 0);  // small name
  put32(c, (4u << 16) | 5u, false); put32(c, 1, false);                             // field name length 1
  put32(c, 1, false); put32(c, 4000, false); c.resize(c.size() + 4000, 'a');
  Bytes e;
  put32(e, 14, false); put32(e, static_cast<std::uint32_t>(c.size()), false);
  e.insert(e.end(), c.begin(), c.end());
  const std::string why = refusal(file_with(e));
  EXPECT_NE(why.find("4000 struct field elements declared, room for at most 0"), std::string::npos) << why;
}

TEST(MatStructure, LibmatioFindingFromFuzzingIsRefusedWithAMessage) {
  const fs::path p = fs::path(amb::test::source_dir()) / "tests/fuzz/known/libmatio-header-sized-allocation.mat";
  ASSERT_TRUE(fs::exists(p));
  std::ifstream in(p, std::ios::binary);
  const Bytes b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_FALSE(refusal(b).empty());
  EXPECT_THROW((void)amb::host::list_mat_variables(p.string()), std::runtime_error);
}

TEST(MatStructure, FunctionHandleIsRefusedAndOpaqueTagsAreBounded) {
  // fuzz_mat_file (1e6 run): a class-16 array whose name tag claims 1.1 GB sent libmatio into
  // allocating and zeroing it (a 10 s time-out per input under ASan).
  Bytes c;
  put32(c, 6, false); put32(c, 8, false); put32(c, 16 /*function*/, false); put32(c, 0, false);
  put32(c, 5, false); put32(c, 8, false); put32(c, 16, false); put32(c, 1, false);
  put32(c, 1, false); put32(c, 0x44000007u, false); c.resize(c.size() + 8, 'f');
  Bytes e;
  put32(e, 14, false); put32(e, static_cast<std::uint32_t>(c.size()), false);
  e.insert(e.end(), c.begin(), c.end());
  std::string why = refusal(file_with(e));
  EXPECT_NE(why.find("function handle"), std::string::npos) << why;
  EXPECT_THROW((void)amb::host::list_mat_variables(write_temp(file_with(e), "function-handle.mat")), std::runtime_error);
  // The same oversized name tag in an opaque object (class 17) is refused by its bound.
  c[8] = 17;
  Bytes o;
  put32(o, 14, false); put32(o, static_cast<std::uint32_t>(c.size() - 16), false);
  o.insert(o.end(), c.begin(), c.begin() + 16);                      // flags
  o.insert(o.end(), c.begin() + 32, c.end());                        // name tag straight after
  why = refusal(file_with(o));
  EXPECT_NE(why.find("opaque object name declares"), std::string::npos) << why;
}

TEST(MatStructure, EveryMeasuredRecordingPasses) {
  const fs::path measured = fs::path(amb::test::shared_dir()) / "data/measured";
  if (!fs::exists(measured)) GTEST_SKIP() << "no ../shared/data/measured next to the repository";
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(measured)) {
    if (e.path().extension() != ".mat") continue;
    std::ifstream in(e.path(), std::ios::binary);
    const Bytes b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NO_THROW(amb::host::check_mat_structure(b, e.path().filename().string())) << e.path().filename();
    ++files;
  }
  EXPECT_GT(files, 0);
}

}  // namespace
