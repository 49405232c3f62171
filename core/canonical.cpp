#include "core/canonical.hpp"

#include <bit>
#include <cstring>

namespace orthosonar {

void CanonicalWriter::put_f32(float v) { put_u32(std::bit_cast<uint32_t>(v)); }

void CanonicalWriter::put_f64(double v) { put_u64(std::bit_cast<uint64_t>(v)); }

void CanonicalWriter::put_bytes(const uint8_t* data, size_t n) {
  if (n == 0) return;
  const size_t at = buf_.size();
  buf_.resize(at + n);
  std::memcpy(buf_.data() + at, data, n);
}

void CanonicalWriter::put_string(std::string_view s) {
  put_u32(static_cast<uint32_t>(s.size()));
  put_bytes(reinterpret_cast<const uint8_t*>(s.data()), s.size());
}

void CanonicalWriter::put_vec3f(const Eigen::Vector3f& v) {
  put_f32(v.x());
  put_f32(v.y());
  put_f32(v.z());
}

void CanonicalWriter::put_points(const std::vector<Eigen::Vector3f>& points) {
  put_u64(points.size());
  for (const auto& p : points) put_vec3f(p);
}

void CanonicalWriter::put_se3(const SE3& T) {
  const auto& m = T.matrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) put_f64(m(r, c));
}

void CanonicalWriter::patch_u32(size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) buf_[at + static_cast<size_t>(i)] = static_cast<uint8_t>(v >> (8 * i));
}

void CanonicalWriter::patch_u64(size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) buf_[at + static_cast<size_t>(i)] = static_cast<uint8_t>(v >> (8 * i));
}

}  // namespace orthosonar
