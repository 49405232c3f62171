#pragma once
// Output digests (SPEC §9): SHA-256 (OpenSSL EVP) of the canonical serialisation of each
// named output (core/canonical.hpp), and an overall hash over the named digests, so
// `orthosonar verify` can say which outputs differ.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::replay {

struct DigestResult {
  std::string overall_hex;                     // 64 lowercase hex digits
  std::map<std::string, std::string> outputs;  // name -> 64 lowercase hex digits
  friend bool operator==(const DigestResult&, const DigestResult&) = default;
};

// Collects named outputs. Adding the same name twice appends to that output's bytes.
// The overall hash is SHA-256 over, for each name in sorted order, the canonical string
// of the name followed by the 32 raw digest bytes: independent of the order of add().
class DigestBuilder {
 public:
  void add(const std::string& name, const std::vector<uint8_t>& bytes);
  void add(const std::string& name, const uint8_t* data, size_t size);
  DigestResult finish() const;

 private:
  std::map<std::string, std::vector<uint8_t>> parts_;
};

// SHA-256 of bytes, lowercase hex.
std::string sha256_hex(const uint8_t* data, size_t size);
// SHA-256 of a file's bytes, read in 1 MiB blocks, lowercase hex. Errors name the file.
Result<std::string> sha256_file_hex(const std::string& path);

// {"overall": "<hex>", "outputs": {"<name>": "<hex>", ...}} (SPEC output contract).
Status write_digest_json(const std::string& path, const DigestResult& digest);
Result<DigestResult> read_digest_json(const std::string& path);

// Names whose hashes differ, or that exist on one side only; sorted.
std::vector<std::string> differing_outputs(const DigestResult& expected, const DigestResult& actual);

}  // namespace orthosonar::replay
