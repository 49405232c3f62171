#include "replay/mcap/mcap_format.hpp"

#include <bit>
#include <limits>

#include <libdeflate.h>

namespace orthosonar::replay::mcap {

uint32_t crc32(uint32_t crc, const uint8_t* data, size_t n) {
  // The MCAP CRC is CRC-32 (ISO-HDLC, zlib's and gzip's): libdeflate's, which folds with
  // carry-less multiplication where the CPU has it (zlib 1.2.13's table-driven loop ran at
  // 1.6 GB/s and was 14 % of a full-resolution replay; docs/BENCHMARKS.md "Replay, stage by
  // stage"). Same values as zlib's for every input (mcap tests check both on random data).
  // Nothing to add leaves the running CRC as it is (libdeflate, like zlib, answers a null
  // buffer with the initial value 0 instead).
  if (n == 0) return crc;
  return static_cast<uint32_t>(libdeflate_crc32(crc, data, n));
}

uint64_t ByteReader::le(int n) {
  const size_t k = static_cast<size_t>(n);
  if (!ok_ || n_ - pos_ < k) {
    ok_ = false;
    return 0;
  }
  uint64_t v = 0;
  for (size_t i = 0; i < k; ++i) v |= static_cast<uint64_t>(p_[pos_ + i]) << (8 * i);
  pos_ += k;
  return v;
}

double ByteReader::f64() { return std::bit_cast<double>(u64()); }

const uint8_t* ByteReader::take(size_t n) {
  if (!ok_ || n_ - pos_ < n) {
    ok_ = false;
    return nullptr;
  }
  const uint8_t* at = p_ + pos_;
  pos_ += n;
  return at;
}

std::string ByteReader::str() {
  const uint32_t len = u32();
  const uint8_t* at = take(len);
  if (at == nullptr) return {};
  return std::string(reinterpret_cast<const char*>(at), len);
}

}  // namespace orthosonar::replay::mcap
