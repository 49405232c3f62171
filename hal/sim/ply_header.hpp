#pragma once
// The PLY header, parsed in one place for every PLY reader (scene meshes, map clouds,
// the report's overlays). Hand-written rather than PCL's: pcl::PLYReader allocates
// whatever count a header claims (an `element vertex 18446744073709551615` ends in
// std::bad_alloc), cannot carry the per-face object_id/semantic labels, and PCL's mesh
// loaders go through VTK.
//
// Bounded: a header is at most kMaxHeaderBytes; every count must parse as an unsigned
// 64-bit integer; and the sum over elements of count × (smallest encoded size of one item)
// must fit in the bytes after end_header (binary: the scalar sizes plus each list's count
// field; ascii: one character and one separator per value). So a header claiming more
// items than its file can hold is an error naming the file and the element, before
// anything is allocated, and a reader can reserve count items safely.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::sim::ply {

enum class Format : uint8_t { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
enum class Type : uint8_t { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

// Bytes of one binary value of type t (1, 2, 4 or 8).
size_t type_size(Type t);

struct Property {
  std::string name;
  Type type = Type::kF32;       // the value type, or a list's item type
  bool is_list = false;
  Type count_type = Type::kU8;  // lists only
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
  // Index of the non-list property `name`, or -1.
  int scalar_index(std::string_view name) const;
};

struct Header {
  Format format = Format::kAscii;
  std::vector<Element> elements;
  uint64_t body_offset = 0;  // file offset of the first byte after end_header's newline
  uint64_t body_bytes = 0;   // file size - body_offset
};

inline constexpr size_t kMaxHeaderBytes = size_t{1} << 20;

// Parses a header from the first bytes of a file (`head` holds at least the whole header
// or the first kMaxHeaderBytes) whose total size is file_size. `path` only names the file
// in errors ("x.ply: header line 3: ...").
Result<Header> parse_header(std::string_view head, uint64_t file_size, const std::string& path);

// Opens `path` and parses its header (reads at most kMaxHeaderBytes).
Result<Header> read_header(const std::string& path);

}  // namespace orthosonar::sim::ply
