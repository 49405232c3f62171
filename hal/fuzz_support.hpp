#pragma once
// Shared by the libFuzzer harnesses (<stage>_fuzz.cpp, built by the fuzz preset; run them
// with tools/fuzz-all). A harness feeds arbitrary bytes to one parser and returns 0: a
// parser may reject its input with an error, never crash, hang, leak, throw past its API
// or read out of bounds (ASan + UBSan report those).
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace orthosonar::fuzz {

inline std::span<const uint8_t> bytes(const uint8_t* data, size_t size) { return {data, size}; }
inline std::string_view text(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A stream harness's input: the first byte sets the read size (1..256 bytes), so frames also
// arrive split across push() calls as from a socket; the rest is the stream. Empty: nothing.
struct Stream {
  size_t step = 1;
  std::span<const uint8_t> bytes;
};
inline std::optional<Stream> as_stream(const uint8_t* data, size_t size) {
  if (size == 0) return std::nullopt;
  return Stream{size_t{data[0]} + 1, {data + 1, size - 1}};
}

// Feeds `in` to push() in pieces of `step` bytes (a stream parser sees frames split across
// reads as from a socket), calling drain() after each piece.
template <class Push, class Drain>
void in_pieces(std::span<const uint8_t> in, size_t step, Push&& push, Drain&& drain) {
  for (size_t at = 0; at < in.size(); at += step) {
    push(in.subspan(at, std::min(step, in.size() - at)));
    drain();
  }
}

// Parsers that read files (memory-mapped MCAP, OBJ/STL meshes, scene YAML) get the input
// through one file per process, rewritten for every input, in $TMPDIR (or /tmp).
class InputFile {
 public:
  explicit InputFile(const std::string& suffix) {
    const char* dir = std::getenv("TMPDIR");
    path_ = std::string(dir && *dir ? dir : "/tmp") + "/orthosonar_fuzz_" +
            std::to_string(::getpid()) + suffix;
  }
  ~InputFile() { std::remove(path_.c_str()); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;

  // Writes the input; aborts (a harness failure, not a finding) if the file cannot be written.
  const std::string& write(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
      std::perror(path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::string path_;
};

}  // namespace orthosonar::fuzz
