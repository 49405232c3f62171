#pragma once
// Internal to orthosonar_ros: what the definition parser (ros_msg.cpp) and the ros1 / CDR encodings (ros_msg_wire.cpp) share.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "replay/ros/ros_msg.hpp"

namespace orthosonar::replay::rosmsg::detail {

// Nesting of message types (definition) and of decoded values: real types nest < 10 deep.
constexpr int kMaxDepth = 32;

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

inline std::optional<uint64_t> parse_uint(std::string_view s) {
  s = trim(s);
  if (s.empty() || s.size() > 18) return std::nullopt;
  uint64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  return v;
}

inline size_t prim_size(Prim p) {
  switch (p) {
    case Prim::kBool: case Prim::kInt8: case Prim::kUint8: return 1;
    case Prim::kInt16: case Prim::kUint16: return 2;
    case Prim::kInt32: case Prim::kUint32: case Prim::kFloat32: return 4;
    case Prim::kInt64: case Prim::kUint64: case Prim::kFloat64: return 8;
    default: return 0;
  }
}

inline std::string hex(const unsigned char* d, size_t n) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  s.reserve(2 * n);
  for (size_t i = 0; i < n; ++i) {
    s.push_back(kHex[d[i] >> 4]);
    s.push_back(kHex[d[i] & 15]);
  }
  return s;
}

}  // namespace orthosonar::replay::rosmsg::detail
