#pragma once
// Explicit little-endian reads and writes over byte buffers. Wire formats are decoded field by
// field with bounds checks; no struct is ever laid over a buffer (no reinterpret_cast).
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace orthosonar::hal::drivers {

using Bytes = std::vector<uint8_t>;

// Reads little-endian fields from a span; every read checks the remaining size and sets
// failed() instead of reading past the end.
class ByteReader {
 public:
  explicit ByteReader(std::span<const uint8_t> data, size_t offset = 0) : d_(data), pos_(offset) {
    if (pos_ > d_.size()) failed_ = true;
  }
  bool failed() const { return failed_; }
  size_t position() const { return pos_; }
  size_t remaining() const { return failed_ ? 0 : d_.size() - pos_; }
  void skip(size_t n) {
    if (!take(n)) return;
    pos_ += n;
  }
  uint8_t u8() { return static_cast<uint8_t>(le(1)); }
  uint16_t u16() { return static_cast<uint16_t>(le(2)); }
  uint32_t u32() { return static_cast<uint32_t>(le(4)); }
  uint64_t u64() { return le(8); }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  float f32() {
    const uint32_t b = u32();
    float f;
    std::memcpy(&f, &b, sizeof f);
    return f;
  }
  double f64() {
    const uint64_t b = u64();
    double f;
    std::memcpy(&f, &b, sizeof f);
    return f;
  }

 private:
  bool take(size_t n) {
    if (failed_ || d_.size() - pos_ < n) {
      failed_ = true;
      return false;
    }
    return true;
  }
  uint64_t le(size_t n) {
    if (!take(n)) return 0;
    uint64_t v = 0;
    for (size_t i = 0; i < n; ++i) v |= static_cast<uint64_t>(d_[pos_ + i]) << (8 * i);
    pos_ += n;
    return v;
  }
  std::span<const uint8_t> d_;
  size_t pos_ = 0;
  bool failed_ = false;
};

// Appends little-endian fields to a byte vector.
class ByteWriter {
 public:
  explicit ByteWriter(Bytes& out) : out_(out) {}
  void u8(uint8_t v) { out_.push_back(v); }
  void u16(uint16_t v) { le(v, 2); }
  void u32(uint32_t v) { le(v, 4); }
  void u64(uint64_t v) { le(v, 8); }
  void i16(int16_t v) { u16(static_cast<uint16_t>(v)); }
  void f32(float f) {
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    u32(b);
  }
  void f64(double f) {
    uint64_t b;
    std::memcpy(&b, &f, sizeof b);
    u64(b);
  }
  void bytes(std::span<const uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }
  // Overwrites a little-endian u32 at an earlier position (sizes known only at the end).
  void patch_u32(size_t at, uint32_t v) {
    for (size_t i = 0; i < 4; ++i) out_[at + i] = static_cast<uint8_t>(v >> (8 * i));
  }

 private:
  void le(uint64_t v, size_t n) {
    for (size_t i = 0; i < n; ++i) out_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  Bytes& out_;
};

inline std::span<const uint8_t> as_bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

}  // namespace orthosonar::hal::drivers
