#pragma once
// Explicit little-endian encoding for on-disk and on-wire formats (independent of the host's
// byte order and struct padding).
//
// A format's field list is written once, as a function template over the coder
// (`template <class Coder, class Rec> void fields(Coder& c, Rec& r)`): ByteWriter's calls take
// the values (Rec is const), ByteReader's same-named calls fill them. So encoder and decoder
// cannot disagree on the order, width or presence of a field.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace amb::fw {

class ByteWriter {
 public:
  explicit ByteWriter(std::vector<uint8_t>& out) : out_(out) {}
  void u8(uint8_t v) { out_.push_back(v); }
  void u16(uint16_t v) { for (int i = 0; i < 2; ++i) out_.push_back(static_cast<uint8_t>(v >> (8 * i))); }
  void u32(uint32_t v) { for (int i = 0; i < 4; ++i) out_.push_back(static_cast<uint8_t>(v >> (8 * i))); }
  void u64(uint64_t v) { for (int i = 0; i < 8; ++i) out_.push_back(static_cast<uint8_t>(v >> (8 * i))); }
  void i64(int64_t v) { u64(static_cast<uint64_t>(v)); }
  void f32(float v) { uint32_t u; std::memcpy(&u, &v, 4); u32(u); }
  void f64(double v) { uint64_t u; std::memcpy(&u, &v, 8); u64(u); }
  /// Fixed-width, zero-padded string field.
  void str(const std::string& s, size_t width) {
    for (size_t i = 0; i < width; ++i) out_.push_back(i < s.size() ? static_cast<uint8_t>(s[i]) : 0);
  }

  // Field-list calls (the same names on ByteReader).
  static constexpr bool k_reads = false;
  /// An enum or bool stored in one byte.
  template <class T> void u8_of(const T& v) { u8(static_cast<uint8_t>(v)); }
  /// A signed value stored as one two's-complement byte.
  template <class T> void i8_of(const T& v) { u8(static_cast<uint8_t>(static_cast<int8_t>(v))); }
  /// Reserved bytes: written as zeros.
  void zeros(size_t bytes) { for (size_t i = 0; i < bytes; ++i) u8(0); }
  /// Text in a `width`-byte field, at most `max_chars` of it stored (the rest zero padding).
  void text(const std::string& s, size_t width, size_t max_chars) { str(s.substr(0, std::min(max_chars, s.size())), width); }
  template <size_t N> void f32s(const std::array<float, N>& a) { for (float v : a) f32(v); }
  template <size_t N> void f64s(const std::array<double, N>& a) { for (double v : a) f64(v); }

 private:
  std::vector<uint8_t>& out_;
};

/// Reads with bounds checking: once a read runs past the end, ok() is false and values are 0.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : p_(data), n_(size) {}
  bool ok() const { return ok_; }
  size_t offset() const { return at_; }
  size_t remaining() const { return n_ - at_; }
  uint8_t u8() { return static_cast<uint8_t>(take(1)); }
  uint16_t u16() { return static_cast<uint16_t>(take(2)); }
  uint32_t u32() { return static_cast<uint32_t>(take(4)); }
  uint64_t u64() { return take(8); }
  int64_t i64() { return static_cast<int64_t>(take(8)); }
  float f32() { const uint32_t u = u32(); float v; std::memcpy(&v, &u, 4); return v; }
  double f64() { const uint64_t u = u64(); double v; std::memcpy(&v, &u, 8); return v; }
  std::string str(size_t width) {
    if (!need(width)) return {};
    std::string s(reinterpret_cast<const char*>(p_ + at_), width);
    at_ += width;
    s.resize(s.find('\0') == std::string::npos ? s.size() : s.find('\0'));
    return s;
  }

  // Field-list calls (the same names on ByteWriter): each fills its argument.
  static constexpr bool k_reads = true;
  void u8(uint8_t& v) { v = u8(); }
  void u16(uint16_t& v) { v = u16(); }
  void u32(uint32_t& v) { v = u32(); }
  void u64(uint64_t& v) { v = u64(); }
  void i64(int64_t& v) { v = i64(); }
  void f32(float& v) { v = f32(); }
  void f64(double& v) { v = f64(); }
  template <class T> void u8_of(T& v) { v = static_cast<T>(u8()); }
  template <class T> void i8_of(T& v) { v = static_cast<T>(static_cast<int8_t>(u8())); }
  /// Reserved bytes: skipped (a format that requires them zero checks that itself).
  void zeros(size_t bytes) { for (size_t i = 0; i < bytes; ++i) (void)u8(); }
  void text(std::string& s, size_t width, size_t /*max_chars*/) { s = str(width); }
  template <size_t N> void f32s(std::array<float, N>& a) { for (float& v : a) v = f32(); }
  template <size_t N> void f64s(std::array<double, N>& a) { for (double& v : a) v = f64(); }

 private:
  bool need(size_t k) {
    if (!ok_ || n_ - at_ < k) { ok_ = false; return false; }
    return true;
  }
  uint64_t take(int bytes) {
    if (!need(static_cast<size_t>(bytes))) return 0;
    uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= static_cast<uint64_t>(p_[at_ + static_cast<size_t>(i)]) << (8 * i);
    at_ += static_cast<size_t>(bytes);
    return v;
  }
  const uint8_t* p_;
  size_t n_;
  size_t at_ = 0;
  bool ok_ = true;
};

}  // namespace amb::fw
