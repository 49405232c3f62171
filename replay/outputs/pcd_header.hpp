#pragma once
// PCD v0.7 headers, validated before pcl::io reads the data. pcl::PCDReader trusts
// WIDTH/HEIGHT/POINTS and resizes its buffer to match (a header claiming 2^64 - 1 points
// ends in std::bad_alloc), so every count is checked here first: each must parse as an
// unsigned 64-bit integer, POINTS must equal WIDTH × HEIGHT, and POINTS × (smallest
// encoded size of one point) must fit in the bytes after the DATA line (binary: the sum
// of SIZE × COUNT; ascii: one character and one separator per value; binary_compressed:
// the sizes in its 8-byte preamble, and an LZF expansion ratio of at most 100). A header
// that claims more than its file holds is an error naming the file and the field.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::outputs::pcd {

enum class Data : uint8_t { kAscii, kBinary, kBinaryCompressed };

struct Field {
  std::string name;
  char type = 'F';     // 'I', 'U' or 'F'
  uint32_t size = 4;   // bytes: 1, 2, 4 or 8
  uint64_t count = 1;  // values per point
};

struct Header {
  std::vector<Field> fields;
  uint64_t width = 0, height = 0, points = 0;
  Data data = Data::kBinary;
  uint64_t point_bytes = 0;  // binary size of one point (sum of size × count)
  uint64_t data_offset = 0;  // file offset of the first byte after the DATA line
  uint64_t data_bytes = 0;   // file size - data_offset
  // The field called `name`, or nullptr.
  const Field* field(std::string_view name) const;
};

inline constexpr size_t kMaxHeaderBytes = size_t{1} << 20;

// `head` holds the first bytes of a file (at least the whole header, or kMaxHeaderBytes)
// whose size is file_size; binary_compressed also needs the 8 bytes after the DATA line.
Result<Header> parse_header(std::string_view head, uint64_t file_size, const std::string& path);
Result<Header> read_header(const std::string& path);

}  // namespace orthosonar::outputs::pcd
