// A read-only memory-mapped file whose pages are released as a reader consumes them
// (replay/mcap/mapped_file.hpp).
#include "replay/mcap/mapped_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include "replay/mcap/mcap_format.hpp"

namespace orthosonar::replay::mcap {

Result<std::unique_ptr<MappedFile>> MappedFile::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Error{path + ": cannot open: " + std::strerror(errno)};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    ::close(fd);
    return Error{path + ": cannot stat"};
  }
  std::unique_ptr<MappedFile> f(new MappedFile());
  f->path_ = path;
  f->size_ = static_cast<size_t>(st.st_size);
  if (f->size_ > 0) {
    void* p = ::mmap(nullptr, f->size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      return Error{path + ": cannot map: " + std::strerror(errno)};
    }
    ::madvise(p, f->size_, MADV_SEQUENTIAL);
    f->data_ = static_cast<const uint8_t*>(p);
  }
  f->fd_ = fd;  // kept for crc32's reads
  return f;
}

void MappedFile::release(uint64_t offset, uint64_t n) const {
  if (data_ == nullptr || offset >= size_ || n == 0) return;
  static const uint64_t page = static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  const uint64_t begin = offset / page * page;
  const uint64_t end = std::min<uint64_t>(size_, offset + std::min<uint64_t>(n, size_ - offset));
  // A read-only file mapping: dropped pages read back the same bytes from the file.
  ::madvise(const_cast<uint8_t*>(data_) + begin, end - begin, MADV_DONTNEED);
}

uint32_t MappedFile::crc32(uint32_t crc, uint64_t offset, uint64_t n) const {
  if (offset >= size_) return crc;
  n = std::min<uint64_t>(n, size_ - offset);
  constexpr uint64_t kBlock = uint64_t{1} << 20;
  if (n < kBlock || fd_ < 0) return mcap::crc32(crc, data_ + offset, n);
  std::vector<uint8_t> buf(kBlock);
  while (n > 0) {
    const uint64_t want = std::min(n, kBlock);
    const ssize_t got = ::pread(fd_, buf.data(), want, static_cast<off_t>(offset));
    if (got <= 0) return mcap::crc32(crc, data_ + offset, n);  // the map has the same bytes
    crc = mcap::crc32(crc, buf.data(), static_cast<size_t>(got));
    offset += static_cast<uint64_t>(got);
    n -= static_cast<uint64_t>(got);
  }
  return crc;
}

const uint8_t* MappedFile::bytes(uint64_t offset, uint64_t n, std::vector<uint8_t>& buf) const {
  constexpr uint64_t kLarge = uint64_t{256} << 10;
  if (n < kLarge || fd_ < 0) return data_ + offset;
  buf.resize(n);
  uint64_t done = 0;
  while (done < n) {
    const ssize_t got = ::pread(fd_, buf.data() + done, n - done, static_cast<off_t>(offset + done));
    if (got <= 0) return data_ + offset;  // the map has the same bytes
    done += static_cast<uint64_t>(got);
  }
  return buf.data();
}

MappedFile::~MappedFile() {
  if (data_ != nullptr) ::munmap(const_cast<uint8_t*>(data_), size_);
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace orthosonar::replay::mcap
