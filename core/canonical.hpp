#pragma once
// A canonical little-endian serialiser (SPEC §9): the byte form that output digests hash,
// also used for the fixed-layout records of the fixture format. Floating-point values are
// written by bit pattern (so -0.0, NaN payloads and every last bit survive), integers in
// little-endian order regardless of the host. No I/O: it only fills a byte vector.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"

namespace orthosonar {

class CanonicalWriter {
 public:
  void put_u8(uint8_t v) { buf_.push_back(v); }
  void put_u16(uint16_t v) { put_le(v, 2); }
  void put_u32(uint32_t v) { put_le(v, 4); }
  void put_u64(uint64_t v) { put_le(v, 8); }
  void put_i16(int16_t v) { put_le(static_cast<uint16_t>(v), 2); }
  void put_i32(int32_t v) { put_le(static_cast<uint32_t>(v), 4); }
  void put_i64(int64_t v) { put_le(static_cast<uint64_t>(v), 8); }
  void put_f32(float v);
  void put_f64(double v);
  void put_bool(bool v) { put_u8(v ? 1 : 0); }
  void put_bytes(const uint8_t* data, size_t n);
  void put_bytes(const std::vector<uint8_t>& v) { put_bytes(v.data(), v.size()); }
  // uint32 byte length, then the bytes (no terminator).
  void put_string(std::string_view s);
  // x, y, z as f32.
  void put_vec3f(const Eigen::Vector3f& v);
  // uint64 count, then each point as put_vec3f.
  void put_points(const std::vector<Eigen::Vector3f>& points);
  // The upper 3x4 block of the matrix, row-major, as 12 f64.
  void put_se3(const SE3& T);

  // Overwrites earlier bytes (for length fields filled in after their content).
  void patch_u32(size_t at, uint32_t v);
  void patch_u64(size_t at, uint64_t v);

  size_t size() const { return buf_.size(); }
  const std::vector<uint8_t>& bytes() const { return buf_; }
  std::vector<uint8_t> take() { return std::move(buf_); }
  void clear() { buf_.clear(); }
  void reserve(size_t n) { buf_.reserve(n); }

 private:
  void put_le(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) buf_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  std::vector<uint8_t> buf_;
};

}  // namespace orthosonar
