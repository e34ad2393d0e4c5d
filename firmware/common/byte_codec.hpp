#pragma once
// Explicit little-endian encoding for on-disk and on-wire formats (independent of the host's
// byte order and struct padding).
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
