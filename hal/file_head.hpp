#pragma once
// The first bytes of a file and its size: what a header parser needs (PLY, PCD), read
// without trusting the file to end where its header says.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/result.hpp"

namespace orthosonar::hal {

struct FileHead {
  std::string bytes;  // at most max_bytes, fewer when the file is shorter
  uint64_t size = 0;  // of the whole file
};

inline Result<FileHead> read_file_head(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::error_code ec;
  FileHead head;
  head.size = std::filesystem::file_size(path, ec);
  if (ec) return Error{path + ": cannot stat (" + ec.message() + ")"};
  head.bytes.assign(static_cast<size_t>(std::min<uint64_t>(head.size, max_bytes)), '\0');
  in.read(head.bytes.data(), static_cast<std::streamsize>(head.bytes.size()));
  head.bytes.resize(static_cast<size_t>(in.gcount()));
  return head;
}

}  // namespace orthosonar::hal
