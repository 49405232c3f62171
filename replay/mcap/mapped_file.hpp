#pragma once
// A read-only memory-mapped file (the MCAP readers' input): pages a reader has consumed are
// released (madvise) so memory does not grow with the file. Errors name the path.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::replay::mcap {

class MappedFile {
 public:
  static Result<std::unique_ptr<MappedFile>> open(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  const uint8_t* data() const { return data_; }
  size_t size() const { return size_; }
  const std::string& path() const { return path_; }
  // Drops the pages of [offset, offset + n) (widened to whole pages) from this process's
  // resident set; the bytes stay readable (a later read faults them back in from the page
  // cache). The scan and read_chunk release what they have consumed, so replaying a
  // recording keeps only the chunks in use resident, not the file (issue 16).
  void release(uint64_t offset, uint64_t n) const;
  // crc32 (mcap_format.hpp) continued over [offset, offset + n), clipped to the file. Large
  // ranges are read with pread instead of through the map: a pass over a whole fixture
  // reads 2.5x faster so (no page-table work), and leaves nothing resident.
  uint32_t crc32(uint32_t crc, uint64_t offset, uint64_t n) const;
  // The bytes [offset, offset + n) (within the file): for large ranges read with pread
  // into `buf` (same reason), else a pointer into the map.
  const uint8_t* bytes(uint64_t offset, uint64_t n, std::vector<uint8_t>& buf) const;

 private:
  MappedFile() = default;
  int fd_ = -1;
  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
  std::string path_;
};

}  // namespace orthosonar::replay::mcap
